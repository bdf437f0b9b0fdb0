"""The audio analysis of the contract ("Signals"), streamed from a file.

:func:`analyse` decodes the first audio stream of a file with PyAV, mixes it to
mono (mean of the channels, float64 in -1..1), runs the bands
(:mod:`marblevideo.signals.bands`) and sums each 10 ms slot
(:mod:`marblevideo.signals.levels`) block after block, the filter state
carried, so an hour of audio never sits in memory: what is kept is 4 floats per
band and slot (100 a second). The result, the RMS r_i of every band on the
100 Hz grid, is cached in memory for the run, keyed by the file's path, size and
modification time and the stream's offset a0.

a0 (seconds) is where the stream's first sample lies on the render's clock:
for a video's own audio, the audio stream's start minus the first video
frame's, both from the container's timestamps (:func:`stream_offset`); 0 for a
soundtrack.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import av
import numpy as np

from marblevideo.errors import MediaError
from marblevideo.signals.bands import BANDS, FilterBank
from marblevideo.signals.levels import Slots

#: Samples per analysed block.
BLOCK = 1 << 16
# Full scale of the integer sample formats (packed and planar alike).
_SCALE = {"u8": 128.0, "s16": 32768.0, "s32": 2.0**31, "s64": 2.0**63}


@dataclass(frozen=True)
class Analysis:
    """r_i, the RMS of each band on the 100 Hz grid from i = 0 to the last window
    holding a sample (windows after it hold none: r = 0), of a stream of ``rate``
    Hz whose first sample lies at ``a0`` seconds."""

    rms: dict[str, np.ndarray]
    rate: int
    a0: float
    path: str


def mono(frame: av.AudioFrame) -> np.ndarray:
    """A decoded frame as the mono mix: the mean of its channels, float64 in -1..1."""
    samples = frame.to_ndarray()
    name = frame.format.name.rstrip("p")
    channels = len(frame.layout.channels)
    if not frame.format.is_planar:
        samples = samples.reshape(-1, channels).T
    samples = samples.astype(np.float64)
    if name == "u8":
        samples -= 128.0
    if name in _SCALE:
        samples /= _SCALE[name]
    return samples.mean(axis=0)


def first_audio(container) -> av.audio.stream.AudioStream | None:
    """The container's first audio stream, or None."""
    return container.streams.audio[0] if container.streams.audio else None


def stream_offset(container) -> Fraction:
    """a0 of a video's own audio: the first audio stream's start minus the first
    video stream's (container timestamps; a missing start counts as 0)."""
    audio, video = first_audio(container), container.streams.video[0]
    start = Fraction(audio.start_time or 0) * audio.time_base
    return start - Fraction(video.start_time or 0) * video.time_base


def blocks(container, stream, size: int = BLOCK) -> Iterator[np.ndarray]:
    """The stream's mono mix in blocks of about ``size`` samples."""
    held: list[np.ndarray] = []
    count = 0
    try:
        for frame in container.decode(stream):
            held.append(mono(frame))
            count += frame.samples
            if count >= size:
                yield np.concatenate(held)
                held, count = [], 0
    except av.error.FFmpegError as exc:
        raise MediaError(f"{container.name}: cannot decode its audio: {exc.strerror}") from None
    if held:
        yield np.concatenate(held)


def analyse_stream(container, a0: Fraction, size: int = BLOCK) -> Analysis:
    """:func:`analyse` of an open container's first audio stream (uncached)."""
    stream = first_audio(container)
    if stream is None:
        raise MediaError(f"{container.name}: no audio stream")
    rate = stream.codec_context.sample_rate or stream.rate
    bank, slots = FilterBank(rate), Slots(rate, a0, BANDS)
    for block in blocks(container, stream, size):
        slots.add(bank(block))
    return Analysis(slots.rms(), rate, float(a0), container.name)


def analyse(path: str | os.PathLike, own: bool, size: int = BLOCK) -> Analysis:
    """The analysis of the first audio stream of the file at ``path``: ``own``, the
    render's input (a0 from its timestamps, :func:`stream_offset`), else a
    soundtrack (a0 = 0). Cached for the run by path, size and modification time."""
    real = os.path.realpath(path)
    try:
        info = os.stat(real)
    except OSError as exc:
        raise MediaError(f"{path}: cannot read: {exc.strerror}") from None
    return _cached(real, info.st_size, info.st_mtime_ns, own, size)


@lru_cache(maxsize=8)
def _cached(path: str, _size: int, _mtime: int, own: bool, size: int) -> Analysis:
    try:
        container = av.open(path)
    except av.error.FFmpegError as exc:
        raise MediaError(f"{path}: not a readable media file ({exc.strerror})") from None
    with container:
        has_video = bool(container.streams.video) and first_audio(container) is not None
        a0 = stream_offset(container) if own and has_video else Fraction(0)
        return analyse_stream(container, a0, size)
