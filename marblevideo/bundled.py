"""The sample files shipped with the package (recipes, and the small images the
README's commands use): in a wheel they lie in ``marblevideo/samples``, in a
source checkout in the repository's ``samples/``.

The sample recipes are the presets: ``--ops swirl`` (or ``swirl.json``) names
``samples/swirl.json`` wherever no file of that name exists (a file always wins).
"""

from __future__ import annotations

import os
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent
#: The recipe JSON Schema among the samples (not a preset).
SCHEMA_FILE = "recipe.schema.json"


def samples_dir() -> Path:
    """The folder of samples: the installed package's, else the source checkout's."""
    installed = _PACKAGE / "samples"
    return installed if installed.is_dir() else _PACKAGE.parent / "samples"


def samples_path(name: str) -> Path:
    """The path of the bundled sample ``name`` (e.g. ``"figure6.json"``);
    FileNotFoundError, naming the samples there are, when it does not exist."""
    folder = samples_dir()
    path = folder / name
    if not path.is_file():
        names = sorted(p.name for p in folder.glob("*") if p.is_file()) if folder.is_dir() else []
        raise FileNotFoundError(
            f"no sample {name!r} in {folder} (there are: {', '.join(names) or 'none'})"
        )
    return path


def presets() -> dict[str, Path]:
    """The bundled recipes, name (the file's stem) -> path, by name."""
    folder = samples_dir()
    return {p.stem: p for p in sorted(folder.glob("*.json")) if p.name != SCHEMA_FILE}


def preset_name(name: str) -> str | None:
    """The preset name ``name`` would stand for (``"swirl"`` for ``"swirl"`` or
    ``"swirl.json"``); None when it has a folder in it (it is only ever a path)."""
    if "/" in name or os.sep in name:
        return None
    return name[:-5] if name.endswith(".json") else name


def preset_path(name: str) -> Path | None:
    """The preset ``name`` or ``name.json``; None when there is none."""
    stem = preset_name(name)
    return None if stem is None else presets().get(stem)


def recipe_file(recipe: str | os.PathLike[str]) -> str | os.PathLike[str]:
    """Where the recipe ``recipe`` is read from: ``recipe`` itself when it exists,
    else the preset of that name if there is one, else ``recipe`` (unreadable)."""
    if os.path.exists(recipe):
        return recipe
    return preset_path(os.fspath(recipe)) or recipe
