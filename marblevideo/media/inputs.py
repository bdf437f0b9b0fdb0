"""Inputs: classified once, at the edge, into an :class:`Input` passed down.

A job's input is one of four kinds: ``blank`` (none: the recipe's sheet),
``image`` (one still: a file, or a still read whole from standard input),
``video`` (a file, a URL, or standard input) and ``sequence`` (an image
sequence ``name_%04d.png``, read as a video). :func:`classify` tells which from
the name (standard input: from its first bytes); :meth:`Input.checked` checks a
local file once. Readers take an :class:`Input` or a name, and classify a name
themselves only when given one.

A missing, folder or empty input is a media fault (exit status 1), reported in
one line naming the file, for stills and video alike.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, replace
from pathlib import Path

from marblevideo.errors import MediaError
from marblevideo.media.formats import is_image_name, is_sequence, is_stdio, is_url

#: The kinds of input, and what a check says was expected of a file of each.
KINDS = {"blank": None, "image": "an image", "video": "a video", "sequence": None}


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


class _Replay:
    """A stream read again from its start: the bytes already read (``head``), then
    the rest of ``raw``. No ``seek``: PyAV treats it as a pipe."""

    def __init__(self, raw, head: bytes):
        self.raw, self.head = raw, head

    def read(self, size: int = -1) -> bytes:
        if self.head:
            cut = len(self.head) if size < 0 else size
            out, self.head = self.head[:cut], self.head[cut:]
            return out
        return self.raw.read(size)


#: How a still image's first bytes look (PNG, JPEG, TIFF, WebP).
_IMAGE_MAGIC = (b"\x89PNG", b"\xff\xd8\xff", b"II*\x00", b"MM\x00*")


def stdin_source() -> tuple[bytes | None, _Replay | None]:
    """Standard input as (the whole of a still image's bytes, None), or (None, a
    readable stream for PyAV) for anything else."""
    raw = sys.stdin.buffer
    head = raw.read(16)
    if not head:
        raise MediaError("-: standard input is empty")
    if head.startswith(_IMAGE_MAGIC) or (head[:4] == b"RIFF" and head[8:12] == b"WEBP"):
        return head + raw.read(), None
    return None, _Replay(raw, head)


@dataclass(frozen=True)
class Input:
    """One input, classified (see the module). ``name``: as given (None for a
    blank sheet); ``path``: the local file once :meth:`checked` (None for
    standard input, URLs and sequences); ``data``: a still's bytes read from
    standard input; ``stream``: standard input to read a video from."""

    kind: str
    name: str | os.PathLike | None = None
    path: Path | None = None
    data: bytes | None = None
    stream: _Replay | None = None

    @property
    def stdin(self) -> bool:
        return is_stdio(self.name)

    @property
    def local(self) -> bool:
        """A name on this machine's file system (a file or a sequence)."""
        return self.name is not None and not self.stdin and not is_url(self.name)

    @property
    def names(self) -> list[str | os.PathLike]:
        """What an output must not overwrite: the local name, if any."""
        return [self.name] if self.local else []

    def checked(self) -> Input:
        """This input with its local file checked (:func:`check_input`) once."""
        expected = KINDS[self.kind]
        if self.path is not None or not self.local or expected is None:
            return self
        return replace(self, path=check_input(self.name, expected))


def name_kind(src: str | os.PathLike | None) -> str:
    """The kind the name ``src`` tells, reading nothing: one of :data:`KINDS`, or
    ``stdin`` (standard input: a still or a video, known once read)."""
    if src is None:
        return "blank"
    if is_stdio(src):
        return "stdin"
    if is_url(src):
        return "video"
    if is_sequence(src):
        return "sequence"
    return "image" if is_image_name(src) else "video"


def classify(src: str | os.PathLike | Input | None) -> Input:
    """``src`` as an :class:`Input` (itself if it is one already). Standard input is
    read to its first bytes: a still is read whole, a video is left to stream."""
    if isinstance(src, Input):
        return src
    kind = name_kind(src)
    if kind != "stdin":
        return Input(kind, src)
    data, stream = stdin_source()
    if data is not None:
        return Input("image", src, data=data)
    return Input("video", src, stream=stream)
