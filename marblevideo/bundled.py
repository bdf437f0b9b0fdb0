"""The sample files shipped with the package (recipes, and the small images the
README's commands use): in a wheel they lie in ``marblevideo/samples``, in a
source checkout in the repository's ``samples/``."""

from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


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
