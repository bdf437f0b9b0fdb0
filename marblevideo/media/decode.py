"""Decoding: an input opened with PyAV (a file, an image sequence, standard
input or a URL), its frames upright (rotation applied) as
RGBA, or as I420 planes that are views of the decoded frame, and its audio in
demux order, trimmed to a range of the input's clock."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.limits import DEFAULT_FPS, URL_TIMEOUT
from marblevideo.media.formats import frame_field, sequence_names
from marblevideo.media.inputs import Input, check_input, classify
from marblevideo.media.video import AudioItem, VideoItem
from marblevideo.media.yuv import FORMATS, YuvMatrix


def input_name(container: av.container.InputContainer) -> str:
    """How messages name an input: its path or URL, ``-`` for standard input."""
    return "-" if container.name in ("", "<none>") else container.name


def packets(container: av.container.InputContainer, streams) -> Iterator[av.Packet]:
    """``container.demux(streams)``; a demuxer's failure is a MediaError in one
    line (from a pipe, with the usual cause: an MP4 whose index comes last)."""
    demuxed = container.demux(streams)
    while True:
        try:
            packet = next(demuxed)
        except StopIteration:
            return
        except av.error.FFmpegError as exc:
            hint = ""
            if container.format.name.startswith("mov") and input_name(container) == "-":
                hint = (
                    "; an MP4 or MOV read from a pipe needs its index first "
                    "(-movflags +faststart), or send Matroska or NUT"
                )
            raise MediaError(
                f"{input_name(container)}: cannot read: {exc.strerror}{hint}"
            ) from None
        yield packet


def open_input(
    src: str | os.PathLike | Input, rate: float | None = None
) -> av.container.InputContainer:
    """Open a video input, or raise MediaError with one line: a file, an image
    sequence (``name_%04d.png``, read at ``rate`` frames per second, numbered
    from its first file), standard input (``-``), or a URL; ``src`` a name or an
    :class:`~marblevideo.media.inputs.Input` classified already."""
    source = classify(src)
    options, fmt = {}, None
    if source.stdin:
        target = source.stream
        if target is None:
            raise MediaError("-: standard input holds a still image, not a video")
    elif not source.local:
        target = os.fspath(source.name)
        options = {"rw_timeout": str(URL_TIMEOUT * 1_000_000)}  # microseconds
    elif source.kind == "sequence":
        target, fmt = os.fspath(source.name), "image2"
        options = {
            "framerate": f"{rate or DEFAULT_FPS:g}",
            "start_number": str(_first(source.name)),
        }
    else:
        target = str(source.path or check_input(source.name, "a video"))
    try:
        container = av.open(target, format=fmt, options=options)
    except av.error.FFmpegError as exc:
        raise MediaError(f"{source.name}: not a readable video ({exc.strerror})") from None
    if not container.streams.video:
        container.close()
        raise MediaError(f"{source.name}: no video stream")
    return container


def _first(pattern: str | os.PathLike) -> int:
    """The number of a sequence's first file; MediaError (like a missing file)
    when it has none."""
    folder = Path(pattern).parent if str(Path(pattern).parent) else Path(".")
    names = sequence_names(pattern, os.listdir(folder)) if folder.is_dir() else []
    if not names:
        raise MediaError(f"{pattern}: no files of this image sequence")
    match = frame_field(pattern)
    head = len(Path(pattern).name[: match.start()])
    tail = len(Path(pattern).name) - match.end()
    return min(int(n[head : len(n) - tail]) for n in names)


def frame_planes(frame: av.VideoFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The I420 planes (y, u, v) of a yuv420p frame: views of its buffers, which
    they keep alive (no copy; rows padded to the frame's line sizes)."""
    return tuple(
        np.frombuffer(plane, np.uint8).reshape(-1, plane.line_size)[: plane.height, : plane.width]
        for plane in frame.planes
    )


#: Decoded formats whose first plane is the 8-bit luma (Y) itself, one byte a pixel.
LUMA_FORMATS = frozenset(
    ("yuv420p", "yuvj420p", "yuv422p", "yuvj422p", "yuv444p", "yuvj444p", "yuv440p", "yuvj440p")
    + ("yuv411p", "yuv410p", "nv12", "nv21", "gray")
)


def frame_luma(frame: av.VideoFrame) -> np.ndarray | None:
    """The frame's luma plane as decoded (its 8-bit Y codes, no conversion), upright
    as :func:`upright` turns it: a view of its buffer where no turn is needed (rows
    padded to the line size), else a copy; None for a frame whose format is not one
    of :data:`LUMA_FORMATS` (RGB, high bit depths: read the RGBA frame instead)."""
    if frame.format.name not in LUMA_FORMATS:
        return None
    plane = frame.planes[0]
    y = np.frombuffer(plane, np.uint8).reshape(-1, plane.line_size)[: frame.height, : frame.width]
    turns = round(frame.rotation / 90) % 4
    return np.ascontiguousarray(np.rot90(y, turns)) if turns else y


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
    ``pts_origin``: video timestamps are given as ``pts - pts_origin`` whatever
    the range (a segment of a split render, :mod:`marblevideo.jobs.segments`);
    by default they are unchanged without a range, else start at 0 at the
    first kept frame. ``luma``: each video item carries its frame's luma plane
    (:func:`frame_luma`), whichever way its pixels travel.
    """

    def __init__(
        self,
        container,
        start: float | None,
        end: float | None,
        audio: dict[int, str],
        i420: bool = False,
        pts_origin: int | None = None,
        luma: bool = False,
    ):
        self.container = container
        self.luma = luma
        self.pts_origin = pts_origin
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
            # a pipe cannot seek: the frames before start are then decoded and dropped
            with contextlib.suppress(av.error.FFmpegError, OSError):
                self.container.seek(target, stream=self.video, backward=True, any_frame=False)
        streams = [self.video] + [self.container.streams[i] for i in self.audio]
        for stream in streams[1:]:
            if self.audio[stream.index] != "copy":
                stream.thread_type = "AUTO"
        held: list[AudioItem] = []
        done = {s.index: False for s in streams}
        for packet in packets(self.container, streams):
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
                for payload in self.audio_payloads(packet):
                    item = AudioItem(index, payload)
                    keep = self._audio_in_range(item)
                    if keep is None:
                        done[index] = True
                        break
                    if self.origin is None:
                        held.append(item)
                    elif keep:
                        yield self._shifted(item)

    def audio_payloads(self, packet: av.Packet) -> list:
        """What an audio packet gives: itself to copy (unless empty), else its
        decoded frames."""
        if self.audio[packet.stream.index] == "copy":
            return [packet] if packet.size else []
        return self._decode(packet)

    def audio_only(self) -> Iterator[AudioItem]:
        """Every audio item of the whole input, in demux order (no video decoded)."""
        streams = [self.container.streams[i] for i in self.audio]
        for stream in streams:
            if self.audio[stream.index] != "copy":
                stream.thread_type = "AUTO"
        for packet in packets(self.container, streams) if streams else ():
            for payload in self.audio_payloads(packet):
                yield AudioItem(packet.stream.index, payload)

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
            raise MediaError(
                f"{input_name(self.container)}: cannot decode: {exc.strerror}"
            ) from None

    def _video_item(self, frame: av.VideoFrame, t: float) -> VideoItem:
        if self.rotation is None:
            self.rotation = frame.rotation
        if self.pts_origin is not None:
            pts = frame.pts - self.pts_origin
        else:
            pts = self._shift(frame.pts, self.tb)
        if (
            self.i420
            and frame.format.name in FORMATS
            and not frame.rotation
            and frame.width % 2 == frame.height % 2 == 0
        ):
            matrix = YuvMatrix.of(frame.colorspace, frame.color_range, frame.format.name)
            if matrix is not None:
                item = VideoItem(None, pts, frame.duration or 0, t, frame_planes(frame), matrix)
                item.luma = item.i420[0] if self.luma else None
                return item
        luma = frame_luma(frame) if self.luma else None
        return VideoItem(upright(frame), pts, frame.duration or 0, t, luma=luma)

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


def estimate_frames(reader: Reader, fps: float | None = None) -> int | None:
    """About how many frames the range holds (at ``fps`` where the rate is
    converted); None where the input does not say."""
    video = reader.video
    rate = fps or video.average_rate or video.guessed_rate
    if video.duration and rate:
        total = float(video.duration * video.time_base)
    elif reader.container.duration and rate:
        total = reader.container.duration / av.time_base
    else:
        return None if fps else video.frames or None
    end = min(reader.end, total) if reader.end is not None else total
    return max(0, round((end - (reader.start or 0)) * float(rate)))


def grab_frame(container, time: float | None) -> tuple[float, np.ndarray]:
    """The frame shown at ``time`` seconds on the input's clock (the clock of the
    transform's ``t``; default: the first frame), as (its time, upright RGBA).
    UsageError when ``time`` is after the last frame."""
    reader = Reader(container, None, None, {})
    video = reader.video
    if time:
        with contextlib.suppress(av.error.FFmpegError, OSError):  # a pipe cannot seek
            container.seek(reader.clock + int(time / reader.tb), stream=video, backward=True)
    shown: tuple[float, av.VideoFrame] | None = None
    for packet in packets(container, video):
        for frame in reader._decode(packet):
            if frame.pts is None:
                continue
            t = reader.seconds(frame.pts)
            if time is None or (shown is not None and t > time + 1e-6):
                return (t, upright(frame)) if time is None else (shown[0], upright(shown[1]))
            if t > time + 1e-6:  # the first frame is after ``time``: the video starts there
                return t, upright(frame)
            shown = (t, frame)
    if shown is None:
        raise MediaError(f"{input_name(container)}: no video frames")
    t, frame = shown
    rate = video.average_rate or video.guessed_rate
    end = t + (float(frame.duration * video.time_base) if frame.duration else 0.0)
    if not frame.duration and rate:
        end = t + 1 / float(rate)
    if time > end + 1e-6:
        raise UsageError(f"--time {time:g}: after the last frame (shown {t:.3f}..{end:.3f} s)")
    return t, upright(frame)
