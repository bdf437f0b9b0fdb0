"""What ``--ops NAME`` means to a session that edits its recipe (``design``,
``live --preview``): a file stays itself, and a preset's name opens a working
copy beside the user, never the installed sample (:mod:`marblevideo.bundled`).

Planning and writing are apart, so that every option is checked before the copy
is written: :func:`plan_working_copy`, then the checks, then :func:`copy_preset`.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

from marblevideo.bundled import preset_path, presets
from marblevideo.errors import OutputExistsError, UsageError
from marblevideo.media.output import atomic_output


def plan_working_copy(name: str, overwrite: bool = False) -> tuple[str, Path | None]:
    """``(file to edit, preset to copy there or None)`` for ``--ops name``; writes nothing.

    ``name`` itself when that file exists, or when no preset has that name (a new
    recipe is then created there). For a preset's name, or the path of a bundled
    preset's own file, ``./<preset>.json`` in the working folder and the preset's
    file; an existing copy is refused without ``overwrite`` (``-y``):
    OutputExistsError (exit 2) names the file to edit instead.
    """
    preset = _bundled(name) if os.path.exists(name) else preset_path(name)
    if preset is None:
        return name, None
    copy = f"{preset.stem}.json"
    if Path(copy).resolve() == preset.resolve():
        raise UsageError(f"{copy}: is the bundled preset; edit a copy from another folder")
    if os.path.exists(copy) and not overwrite:
        raise OutputExistsError(
            f"{copy}: already exists; edit it with --ops ./{copy}, "
            f"or use -y to start again from the preset {preset.stem!r}"
        )
    return copy, preset


def _bundled(path: str) -> Path | None:
    """The preset whose installed file ``path`` is, or None."""
    here = Path(path).resolve()
    return next((p for p in presets().values() if p.resolve() == here), None)


def copy_preset(preset: Path, copy: str, quiet: bool = False) -> None:
    """Write the preset's JSON to ``copy`` (atomically) and say so unless ``quiet``."""
    with atomic_output(copy, overwrite=True) as tmp:
        shutil.copyfile(preset, tmp)
    if not quiet:
        print(
            f"marblevideo: editing {copy}, a copy of the preset {preset.stem!r} "
            "(the bundled sample is never changed)",
            file=sys.stderr,
            flush=True,
        )
