"""Input files: the checks every reader makes before decoding.

A missing input or a folder is the user's mistake (exit status 2); an empty
file is a media fault (exit status 1), like any unreadable one. Each is one
line naming the file, for stills and video alike.
"""

from __future__ import annotations

import os
from pathlib import Path

from marblevideo.errors import MediaError, UsageError


def check_input(path: str | os.PathLike, kind: str) -> Path:
    """``path`` as a Path; UsageError if it is missing or a folder, MediaError if
    it is empty.
    ``kind`` names what was expected ("an image", "a video")."""
    path = Path(path)
    if not path.exists():
        raise UsageError(f"{path}: no such file")
    if path.is_dir():
        raise UsageError(f"{path}: is a folder, not {kind}")
    if path.stat().st_size == 0:
        raise MediaError(f"{path}: empty file")
    return path
