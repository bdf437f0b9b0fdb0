"""Safe output files: nothing is lost, nothing half-written is left behind.

:func:`atomic_output` hands out a temporary path beside the target (same
folder, same extension, so format detection by extension still works), and
renames it over the target only when the block completes. On any exception,
KeyboardInterrupt included, the temporary file is removed. An existing target
is replaced only with ``overwrite=True``; a target that is one of the inputs is
refused outright.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from marblevideo.errors import MediaError, OutputExistsError, UsageError
from marblevideo.media.formats import is_sequence, is_stdio, sequence_names


def check_output(
    dst: str | os.PathLike, overwrite: bool = False, inputs: Iterable[str | os.PathLike] = ()
) -> Path | str:
    """The one output check, before any work: refuse an output that would harm an
    input, exists without ``overwrite``, or lies in a folder that does not exist.
    An image sequence (``name_%04d.png``) is refused when any of its frames exists;
    ``-`` (standard output) is always free. Returns the target as a Path (``-`` as
    it is)."""
    if is_stdio(dst):
        return os.fspath(dst)
    target = Path(dst)
    if is_sequence(dst):
        _check_sequence(target, overwrite)
        return target
    for src in inputs:
        if src is None:
            continue
        src = Path(src)
        same = src.exists() and target.exists() and os.path.samefile(src, target)
        if same or src.resolve() == target.resolve():
            raise UsageError(f"{target}: output is the same file as the input; choose another -o")
    refuse_folder(target)
    if str(target.parent) and not target.parent.exists():
        raise UsageError(f"{target}: folder {target.parent} does not exist")
    if target.exists() and not overwrite:
        raise OutputExistsError(f"{target}: already exists; use -y to overwrite")
    return target


def refuse_folder(target: str | os.PathLike) -> None:
    """UsageError when the output ``target`` is a folder."""
    if Path(target).is_dir():
        raise UsageError(f"{target}: output is a folder; give a file name")


def _check_sequence(pattern: Path, overwrite: bool) -> None:
    """Refuse a sequence whose folder is missing, or whose frames exist already
    (without ``overwrite``)."""
    folder = pattern.parent if str(pattern.parent) else Path(".")
    if not folder.is_dir():
        raise UsageError(f"{pattern}: folder {folder} does not exist")
    taken = sequence_names(pattern, os.listdir(folder))
    if taken and not overwrite:
        raise OutputExistsError(f"{folder / taken[0]}: already exists; use -y to overwrite")


def _set_mode(tmp: Path, target: Path) -> None:
    """Give the temporary file (mkstemp makes it 0600) the mode the target would get
    from a plain open(): the existing target's, else 0666 less the umask."""
    try:
        mode = target.stat().st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    with contextlib.suppress(OSError):
        os.chmod(tmp, mode)


@contextlib.contextmanager
def atomic_output(
    dst: str | os.PathLike, overwrite: bool = False, inputs: Iterable[str | os.PathLike] = ()
) -> Iterator[Path]:
    """Yield a temporary path beside ``dst``; on success rename it to ``dst``."""
    target = check_output(dst, overwrite, inputs)
    folder = target.parent if str(target.parent) else Path(".")
    try:
        fd, tmp_name = tempfile.mkstemp(
            prefix=f".{target.stem}.", suffix=f".part{target.suffix}", dir=folder
        )
    except OSError as exc:
        raise MediaError(f"{target}: cannot write in {folder}: {exc.strerror}") from None
    os.close(fd)
    tmp = Path(tmp_name)
    _set_mode(tmp, target)
    try:
        yield tmp
        if target.exists() and not overwrite:  # appeared while we worked
            raise OutputExistsError(f"{target}: already exists; use -y to overwrite")
        os.replace(tmp, target)
    except OSError as exc:
        if isinstance(exc, OutputExistsError | MediaError):
            raise
        raise MediaError(f"{target}: cannot write: {exc.strerror or exc}") from None
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
