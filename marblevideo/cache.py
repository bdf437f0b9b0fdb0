"""Where marblevideo keeps what it could recompute, to start sooner the next time
(the digests of recipe files the schema accepted, :mod:`marblevideo.recipe.accepted`;
built OpenCL programs, :mod:`marblevideo.opencl.binaries`): ``$MARBLEVIDEO_CACHE``,
else ``$XDG_CACHE_HOME/marblevideo``, else ``~/.cache/marblevideo``.
``MARBLEVIDEO_CACHE=off`` keeps nothing; so does a folder that cannot be made.
Every entry is checked or keyed so that a stale one is never used."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

#: Environment variable naming the cache folder (``off``: no cache).
CACHE_VARIABLE = "MARBLEVIDEO_CACHE"


def cache_dir(part: str) -> Path | None:
    """The cache's folder ``part``, made if needed; None when caching is off or the
    folder cannot be made."""
    chosen = os.environ.get(CACHE_VARIABLE)
    if chosen == "off":
        return None
    if chosen:
        root = Path(chosen)
    else:
        xdg = os.environ.get("XDG_CACHE_HOME")
        root = (Path(xdg) if xdg else Path.home() / ".cache") / "marblevideo"
    folder = root / part
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return folder


def write_atomically(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` whole or not at all (a reader never sees half of
    it); a failure (a full disk, a read-only cache) is ignored: it is a cache."""
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    except OSError:
        return
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
