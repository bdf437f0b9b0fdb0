"""Built programs kept between processes, as the device's binaries
(clGetProgramInfo's, as pyopencl's own cache does for drivers without one).

PoCL caches its compilation of a source itself, but finding it there (the whole
source compiled to a hash, for every process) took 0.057 s for a recipe's
program on the machine of BENCHMARKS.md (start-up), and creating the program
from its binary 0.022 s. An entry is keyed on the source, the build options,
the device, its driver and platform versions and PoCL's settings (``POCL_*``),
so a changed kernel, driver or target never meets a stale binary. It holds the
binary's SHA-256 before it, and one that does not match is never handed to the
driver (PoCL crashes on a truncated binary); one the driver refuses is built
again from source. The :data:`KEEP` used last are kept, in the cache's
``programs`` folder (:mod:`marblevideo.cache`)."""

from __future__ import annotations

import contextlib
import hashlib
import os
from pathlib import Path

from marblevideo.cache import cache_dir, write_atomically

#: How many programs' binaries are kept (the least recently used go first).
KEEP = 96
_SUFFIX = ".bin"
_DIGEST = 32  # bytes of SHA-256
_POCL_CACHE = "POCL_CACHE_DIR"  # where PoCL keeps its own: no part of what it builds


def binary_key(device, source: str, options: list[str]) -> str:
    """The digest a program of ``source`` built with ``options`` for ``device``
    (a pyopencl Device) is kept under."""
    platform = device.platform
    settings = os.environ.items()
    driver = sorted(f"{k}={v}" for k, v in settings if k.startswith("POCL_") and k != _POCL_CACHE)
    parts = (
        *driver,  # PoCL's settings (POCL_KERNELLIB_NAME: the instruction set built for)
        device.name,
        device.version,
        device.driver_version,
        platform.name,
        platform.version,
        "\0".join(options),
        source,
    )
    return hashlib.sha256("\0\0".join(parts).encode("utf-8", "surrogatepass")).hexdigest()


def _path(key: str) -> Path | None:
    folder = cache_dir("programs")
    return None if folder is None else folder / f"{key}{_SUFFIX}"


def load_binary(key: str) -> bytes | None:
    """The binary kept under ``key``, or None (marked as used: kept longer)."""
    path = _path(key)
    if path is None:
        return None
    try:
        data = path.read_bytes()
    except OSError:
        return None
    digest, binary = data[:_DIGEST], data[_DIGEST:]
    if not binary or hashlib.sha256(binary).digest() != digest:
        return None
    with contextlib.suppress(OSError):
        os.utime(path)
    return binary


def store_binary(key: str, binary: bytes) -> None:
    """Keep ``binary`` under ``key``, and only the :data:`KEEP` used last."""
    path = _path(key)
    if path is None or not binary:
        return
    write_atomically(path, hashlib.sha256(binary).digest() + binary)
    entries = []
    for entry in path.parent.glob(f"*{_SUFFIX}"):
        with contextlib.suppress(OSError):
            entries.append((entry.stat().st_mtime_ns, entry))
    for _, entry in sorted(entries)[:-KEEP]:
        with contextlib.suppress(OSError):
            entry.unlink()
