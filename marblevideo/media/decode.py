"""Decoding: an input opened with PyAV, its frames upright (rotation applied) as
RGBA, or as I420 planes that are views of the decoded frame, and its audio in
demux order, trimmed to a range of the input's clock."""

from __future__ import annotations

import os
from collections.abc import Iterator
from fractions import Fraction

import av
import numpy as np

from marblevideo.errors import MediaError
from marblevideo.media.inputs import check_input
from marblevideo.media.video import AudioItem, VideoItem
from marblevideo.media.yuv import FORMATS, YuvMatrix


def open_input(src: str | os.PathLike) -> av.container.InputContainer:
    """Open a file with a video stream, or raise MediaError with one line."""
    path = check_input(src, "a video")
    try:
        container = av.open(str(path))
    except av.error.FFmpegError as exc:
        raise MediaError(f"{src}: not a readable video ({exc.strerror})") from None
    if not container.streams.video:
        container.close()
        raise MediaError(f"{src}: no video stream")
    return container


def frame_planes(frame: av.VideoFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The I420 planes (y, u, v) of a yuv420p frame: views of its buffers, which
    they keep alive (no copy; rows padded to the frame's line sizes)."""
    return tuple(
        np.frombuffer(plane, np.uint8).reshape(-1, plane.line_size)[: plane.height, : plane.width]
        for plane in frame.planes
    )


def upright(frame: av.VideoFrame) -> np.ndarray:
    """The frame as the viewer sees it: RGBA, display rotation applied, C-contiguous."""
    rgba = frame.to_ndarray(
        format="rgba", src_colorspace=frame.colorspace, src_color_range=frame.color_range
    )
    turns = round(frame.rotation / 90) % 4  # counter-clockwise quarter turns
    return np.ascontiguousarray(np.rot90(rgba, turns) if turns else rgba)


class Reader:
    """Demux and decode one input: upright video frames in the range, plus audio.

    ``audio`` maps input audio stream index -> "copy" (packets) or an encoder
    name (decoded frames). Undecodable packets are counted in ``corrupt``.
    """

    def __init__(
        self,
        container,
        start: float | None,
        end: float | None,
        audio: dict[int, str],
        i420: bool = False,
    ):
        self.container = container
        self.i420 = i420  # hand over upright, even-sized 8-bit 4:2:0 frames as I420
        self.video = container.streams.video[0]
        self.video.thread_type = "AUTO"
        self.tb = self.video.time_base
        self.clock = self.video.start_time or 0  # pts of t = 0
        self.start, self.end = start, end
        self.trim = start is not None or end is not None
        self.audio = audio
        self.corrupt = 0
        self.origin: float | None = None if self.trim else 0.0  # seconds shifted off
        self.rotation: int | None = None

    def seconds(self, pts: int) -> float:
        return float((pts - self.clock) * self.tb)

    def items(self) -> Iterator[VideoItem | AudioItem]:
        """Yield video and audio items in demux order (audio held until the origin is known)."""
        if self.start:
            target = self.clock + int(self.start / self.tb)
            self.container.seek(target, stream=self.video, backward=True, any_frame=False)
        streams = [self.video] + [self.container.streams[i] for i in self.audio]
        for stream in streams[1:]:
            if self.audio[stream.index] != "copy":
                stream.thread_type = "AUTO"
        held: list[AudioItem] = []
        done = {s.index: False for s in streams}
        for packet in self.container.demux(streams):
            index = packet.stream.index
            if done[index]:
                if all(done.values()):
                    break
                continue
            if index == self.video.index:
                for frame in self._decode(packet):
                    if frame.pts is None:
                        continue
                    t = self.seconds(frame.pts)
                    if self.start is not None and t < self.start - 1e-6:
                        continue
                    if self.end is not None and t >= self.end - 1e-6:
                        done[index] = True
                        break
                    if self.origin is None:
                        self.origin = float((frame.pts - self.clock) * self.tb)
                        yield from (self._shifted(a) for a in held if self._audio_in_range(a))
                        held.clear()
                    yield self._video_item(frame, t)
            else:
                copy = self.audio[index] == "copy"
                payloads = ([packet] if packet.size else []) if copy else self._decode(packet)
                for payload in payloads:
                    item = AudioItem(index, payload)
                    keep = self._audio_in_range(item)
                    if keep is None:
                        done[index] = True
                        break
                    if self.origin is None:
                        held.append(item)
                    elif keep:
                        yield self._shifted(item)

    def _audio_in_range(self, item: AudioItem) -> bool | None:
        """True: keep; False: before the range; None: past its end."""
        pts = item.payload.pts
        if not self.trim or pts is None:
            return True
        t = float(pts * item.payload.time_base) - float(self.clock * self.tb)
        if self.end is not None and t >= self.end:
            return None
        origin = self.origin if self.origin is not None else self.start or 0.0
        return t >= origin - 1e-6

    def _decode(self, packet: av.Packet) -> list:
        try:
            return packet.decode()
        except av.error.InvalidDataError:
            self.corrupt += 1
            return []
        except av.error.FFmpegError as exc:
            raise MediaError(f"{self.container.name}: cannot decode: {exc.strerror}") from None

    def _video_item(self, frame: av.VideoFrame, t: float) -> VideoItem:
        if self.rotation is None:
            self.rotation = frame.rotation
        pts = self._shift(frame.pts, self.tb)
        if (
            self.i420
            and frame.format.name in FORMATS
            and not frame.rotation
            and frame.width % 2 == frame.height % 2 == 0
        ):
            matrix = YuvMatrix.of(frame.colorspace, frame.color_range, frame.format.name)
            if matrix is not None:
                return VideoItem(None, pts, frame.duration or 0, t, frame_planes(frame), matrix)
        return VideoItem(upright(frame), pts, frame.duration or 0, t)

    def _shifted(self, item: AudioItem) -> AudioItem:
        payload = item.payload
        payload.pts = self._shift(payload.pts, payload.time_base)
        if isinstance(payload, av.Packet):
            payload.dts = self._shift(payload.dts, payload.time_base)
        return item

    def _shift(self, pts: int | None, time_base: Fraction) -> int | None:
        """Move an input timestamp to the output clock (unchanged without a range)."""
        if pts is None or not self.trim:
            return pts
        return pts - round((self.origin + float(self.clock * self.tb)) / time_base)


def estimate_frames(reader: Reader) -> int | None:
    video = reader.video
    rate = video.average_rate or video.guessed_rate
    if video.duration and rate:
        total = float(video.duration * video.time_base)
    elif reader.container.duration and rate:
        total = reader.container.duration / av.time_base
    else:
        return video.frames or None
    end = min(reader.end, total) if reader.end is not None else total
    return max(0, round((end - (reader.start or 0)) * float(rate)))
