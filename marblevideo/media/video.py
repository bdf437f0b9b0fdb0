"""What a video job is: its options, what it did (:class:`Stats`), the items
that travel through the pipeline (a frame, or an audio packet or frame), and
its one-line notices. Conventions of the whole job: :mod:`~marblevideo.jobs.pipeline`."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from marblevideo.errors import UsageError
from marblevideo.media.yuv import YuvMatrix

if TYPE_CHECKING:
    import av

QUEUE_FRAMES = 4
AUDIO_MODES = ("auto", "copy", "aac", "none")


@dataclass
class VideoOptions:
    """Options of a video job; the fields mirror the command line's flags."""

    codec: str | None = None  # --codec: encoder name; default from the extension
    crf: int | None = None  # --crf: constant quality (x264 23, x265 28, VP9 31)
    preset: str | None = None  # --preset: x264/x265 speed preset (medium)
    pix_fmt: str | None = None  # --pix-fmt; default the format's (yuv420p, GIF pal8, APNG rgb24)
    encoder_opts: dict[str, str] = field(default_factory=dict)  # --encoder-opt KEY=VALUE
    audio: str = "auto"  # --audio auto|copy|aac|none (auto: copy, AAC where it would not play)
    start: float | None = None  # --start: seconds on the input's clock
    end: float | None = None  # --end: seconds on the input's clock (exclusive)
    size: tuple[int, int] | None = None  # --size W H: what the transform produces
    overwrite: bool = False  # -y
    quiet: bool = False  # --quiet: no progress bar, no notices on stderr
    progress: str = "auto"  # --progress auto|bar|json|off
    notify: Callable[[str], None] | None = None  # one-line notices; default stderr
    verbose: bool = False  # --verbose: the encoder libraries' and FFmpeg's own log lines
    format: str | None = None  # --format: the output format by name (needed for -o -)
    fps: float | None = None  # --fps: convert a video's rate; an image sequence's input rate
    duration: float | None = None  # --duration: seconds written (a video's: from start)
    fit: str | None = None  # --fit stretch|crop|pad: an input of another aspect than --size
    soundtrack: str | None = None  # --soundtrack FILE: the output's audio (first sample at t = 0)
    exact_walk: bool = False  # --exact-walk: animated frames walk every subsample (no lattice)


@dataclass
class Stats:
    """What a job did."""

    frames: int = 0
    size: tuple[int, int] | None = None  # (width, height) as encoded
    audio: str = "none"  # "copy", the re-encoder's name, or "none"
    audio_packets: int = 0  # packets copied or encoded
    corrupt_packets: int = 0  # input packets skipped as undecodable
    i420_frames: int = 0  # frames the transform took and gave as I420 (no swscale)
    seconds: float = 0.0  # wall time
    duration: float = 0.0  # seconds of video written: first frame's start to last one's end
    notes: list[str] = field(default_factory=list)

    @property
    def fps(self) -> float:
        return self.frames / self.seconds if self.seconds > 0 else 0.0

    def summary(self, path: str | os.PathLike) -> str:
        """One line for the end of a job: ``wrote PATH: N frames, D s, WxH, F fps``
        (the size as encoded; fps: frames per second of wall time)."""
        size = "x".join(map(str, self.size)) if self.size else "no size"
        return (
            f"wrote {path}: {self.frames} frames, {self.duration:.2f} s, {size}, {self.fps:.1f} fps"
        )


@dataclass
class VideoItem:
    """One frame on its way through the pipeline: its pixels (RGBA or I420), its
    output pts and duration in the encoder's time base, and its time ``t``."""

    rgba: np.ndarray | None  # upright RGBA, or None when the frame travels as I420
    pts: int
    duration: int
    t: float
    i420: np.ndarray | tuple | None = None  # I420, packed or as planes (marblevideo.media.yuv)
    matrix: YuvMatrix | None = None  # the colour matrix and range of ``i420``
    key: bool = False  # encode as a keyframe (a stream's keyframes by time)
    #: the frame's luma plane as decoded (8-bit Y, upright) where the job asks for it
    #: (a recipe's ``motion`` reads it) and the frame has one; None: read ``rgba``
    luma: np.ndarray | None = None

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width) of the frame."""
        if isinstance(self.i420, np.ndarray):  # packed: the rows of Y, then U and V
            return self.i420.shape[0] * 2 // 3, self.i420.shape[1]
        if self.i420 is not None:  # planes (y, u, v)
            return self.i420[0].shape
        return self.rgba.shape[:2]


@dataclass
class AudioItem:
    """An audio packet to copy, or a decoded frame to encode, of input stream ``index``."""

    index: int  # input stream index
    payload: av.Packet | av.AudioFrame  # packet to copy or frame to encode


class Span:
    """The span of the frames written, in their time base: first pts, last pts,
    end of the last frame (a frame without a duration lasts as long as the gap
    before it)."""

    def __init__(self):
        self.bounds: list[int] = []

    def extend(self, item: VideoItem) -> None:
        if not self.bounds:
            self.bounds = [item.pts, item.pts, item.pts + item.duration]
            return
        step = item.duration or item.pts - self.bounds[1]
        self.bounds[1:] = [item.pts, max(self.bounds[2], item.pts + step)]

    def seconds(self, time_base) -> float:
        return float((self.bounds[2] - self.bounds[0]) * time_base) if self.bounds else 0.0


def notify(options: VideoOptions, stats: Stats, message: str) -> None:
    """A job's one-line notice: noted in ``stats`` and told (``options.notify``, else
    stderr unless quiet)."""
    stats.notes.append(message)
    if options.notify is not None:
        options.notify(message)
    elif not options.quiet:
        print(f"marblevideo: {message}", file=sys.stderr, flush=True)


def job_notify(options: VideoOptions, stats: Stats) -> Callable[[str], None]:
    """:func:`notify` bound to a job's ``options`` and ``stats``: the ``notify(message)``
    handed to its parts."""
    return lambda message: notify(options, stats, message)


def check_range(start: float | None, end: float | None) -> None:
    if start is not None and start < 0:
        raise UsageError(f"start must be >= 0 seconds, got {start}")
    if end is not None and end <= (start or 0):
        raise UsageError(f"end ({end} s) must be after start ({start or 0} s)")
