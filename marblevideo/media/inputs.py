"""Input files: the checks every reader makes before decoding.

A missing, folder or empty input is a media fault (exit status 1), reported in
one line naming the file, for stills and video alike.
"""

from __future__ import annotations

import os
from pathlib import Path

from marblevideo.errors import MediaError


def check_input(path: str | os.PathLike, kind: str) -> Path:
    """``path`` as a Path, or MediaError if it is missing, a folder or empty.
    ``kind`` names what was expected ("an image", "a video")."""
    path = Path(path)
    if not path.exists():
        raise MediaError(f"{path}: no such file")
    if path.is_dir():
        raise MediaError(f"{path}: is a folder, not {kind}")
    if path.stat().st_size == 0:
        raise MediaError(f"{path}: empty file")
    return path
