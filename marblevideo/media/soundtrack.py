"""``--soundtrack FILE`` as the output's audio: the file's first audio stream,
its first sample at t = 0 of the render's clock (where the input's first frame
is, or a blank sheet's first), in place of the input's audio.

Its packets are copied (or its frames re-encoded, as the output's audio plan
says: :func:`~marblevideo.media.encode.audio_plan`) and interleaved with the
video by time; what lies before the output's first frame (a render from
``--start``) is left out, and it stops where the video ends.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from fractions import Fraction

import av

from marblevideo.errors import MediaError
from marblevideo.media.decode import packets
from marblevideo.media.encode import OutputPlan, audio_plan
from marblevideo.media.video import AudioItem, VideoItem, VideoOptions


class Soundtrack:
    """An open soundtrack file (a context manager)."""

    def __init__(self, path: str | os.PathLike):
        self.path = os.fspath(path)
        try:
            self.container = av.open(self.path)
        except av.error.FFmpegError as exc:
            raise MediaError(f"{path}: not a readable sound file ({exc.strerror})") from None
        if not self.container.streams.audio:
            self.container.close()
            raise MediaError(f"{path}: no audio stream")
        self.stream = self.container.streams.audio[0]
        self.how: str | None = None

    def __enter__(self) -> Soundtrack:
        return self

    def __exit__(self, *exc) -> None:
        self.container.close()

    def plan(self, plan: OutputPlan, options: VideoOptions, notify) -> dict[int, str]:
        """{stream index: "copy" or the encoder} for the output, or {} (no audio)."""
        name = "standard output" if plan.stream else "the output"
        full = audio_plan(self.container, plan, options, name, notify)
        self.how = full.get(self.stream.index)
        return {} if self.how is None else {self.stream.index: self.how}

    def items(self) -> Iterator[tuple[float, AudioItem]]:
        """(seconds from the stream's first sample, item) in stream order."""
        if self.how is None:
            return
        start = self.stream.start_time or 0
        for packet in packets(self.container, [self.stream]):
            if self.how == "copy":
                payloads = [packet] if packet.size and packet.pts is not None else []
            else:
                payloads = [f for f in packet.decode() if f.pts is not None]
            for payload in payloads:
                yield (
                    float((payload.pts - start) * payload.time_base),
                    AudioItem(self.stream.index, payload),
                )

    def mixed(
        self, items: Iterator[VideoItem | AudioItem], time_base: Fraction
    ) -> Iterator[VideoItem | AudioItem]:
        """The video ``items`` (pts in ``time_base``) with this sound interleaved:
        before each frame, the sound that starts before it; after the last, the
        sound up to its end."""
        sound = self.items()
        pending = next(sound, None)
        shift: float | None = None  # output clock minus render clock, seconds
        end = 0.0
        for item in items:
            if not isinstance(item, VideoItem):
                continue  # the input's own audio is replaced
            if shift is None:
                shift = float(item.pts * time_base) - item.t
            while pending is not None and pending[0] < item.t:
                yield from _placed(pending, shift)
                pending = next(sound, None)
            end = max(end, item.t + float((item.duration or 1) * time_base))
            yield item
        while shift is not None and pending is not None and pending[0] < end:
            yield from _placed(pending, shift)
            pending = next(sound, None)


def _placed(pending: tuple[float, AudioItem], shift: float) -> Iterator[AudioItem]:
    """The item moved to the output clock; nothing where it would start before 0."""
    t, item = pending
    payload = item.payload
    pts = round((t + shift) / payload.time_base)
    if pts < 0:
        return
    if isinstance(payload, av.Packet) and payload.dts is not None:
        payload.dts = pts - (payload.pts - payload.dts)
    payload.pts = pts
    yield item


def opened(path: str | os.PathLike | None):
    """The open soundtrack at ``path``, or a context of None when there is none."""
    return Soundtrack(path) if path else contextlib.nullcontext()
