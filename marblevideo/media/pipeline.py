"""Video I/O: decode with PyAV, hand each upright RGBA frame to a transform, encode.

Conventions
-----------
- A transform is ``transform(rgba, t) -> rgba``: ``rgba`` is a C-contiguous
  ``(H, W, 4)`` uint8 frame, upright (the input's rotation metadata applied,
  multiples of 90 degrees; flips in the display matrix are ignored); ``t`` is
  its presentation time in seconds on the input's own clock,
  ``(pts - stream.start_time) * time_base``, so the first frame of the input
  file has ``t = 0`` whatever ``start`` is. It returns a C-contiguous
  ``(h, w, 4)`` uint8 frame; every frame must have the first one's size.
- Timing: every decoded frame in the range is encoded with its own pts, in the
  input video stream's time base where the container allows (Matroska/WebM
  store 1/1000), so variable frame rates survive. Without ``start``/``end`` the
  pts are copied unchanged; with a range the output starts at 0 at the first
  kept frame (``start``/``end`` are seconds on the same clock as ``t``; frames
  with ``start <= t < end`` are kept) and audio is shifted by the same amount.
  Matroska/WebM cannot start below 0: when copied AAC audio starts at a
  negative time (encoder priming), the muxer shifts all streams alike, as
  ffmpeg does, so A/V sync is kept.
- Audio: ``"copy"`` muxes the input packets unchanged (bit-exact), trimmed to the
  range at packet granularity; where the container cannot hold the codec it is
  re-encoded (AAC; Opus for WebM) with a one-line notice. ``"aac"`` always
  re-encodes to AAC (refused for WebM), ``"none"`` drops audio.
- The output is written upright without rotation metadata; colour range,
  matrix, primaries and transfer of the input are tagged on the output and used
  for the RGBA <-> YUV conversions. With a chroma-subsampled ``pix_fmt``
  (yuv420p) an odd width or height is padded by one replicated edge pixel, and
  a one-line notice says so.
- A transform may also offer ``transform.i420(planes, t, src, dst) -> planes``:
  the frame as I420 planes ``(y, u, v)`` (:mod:`marblevideo.media.yuv`; views of the
  decoded frame's buffers, rows possibly padded: read them, do not keep them)
  with colours in the :class:`~marblevideo.media.yuv.YuvMatrix` ``src``, the result as
  I420 in ``dst``, packed or as planes, in arrays of its own (a packed result
  is encoded without a copy). With ``transform.i420_start(planes, t, src, dst)
  -> finish`` as well, the pipeline keeps one frame in flight: it starts frame
  n + 1 before calling frame n's ``finish()``, which returns what ``i420``
  would have, so a device renders while the host prepares the next frame
  (:meth:`marblevideo.api.VideoTransform.i420_start`); the planes stay the
  pipeline's until ``finish`` returns. ``transform.rgba_start(rgba, t) ->
  finish`` does the same for frames that go the RGBA way.
  It is used for every frame that is 8-bit 4:2:0, upright and even-sized, with
  a supported matrix, when the output is yuv420p of even size. The marbler
  warps the planes themselves when ``src`` and ``dst`` are the same matrix
  (the usual case: the output keeps the input's tags), else it converts on
  the OpenCL device; either way neither swscale conversion runs. Luma differs
  from the RGBA path by a level or two (swscale rounds with less precision);
  chroma is resampled at chroma resolution (see :mod:`marblevideo.media.yuv`).
  :attr:`Stats.i420_frames` counts these frames.
- Packets the decoder rejects as invalid data are skipped and counted, with a
  one-line notice at the end (decoders that conceal damage, like H.264, report
  nothing, as in ffmpeg).
- Notices (one line each) go to ``options.notify``, else to stderr prefixed by
  ``marblevideo:`` (not when ``quiet``); they are also listed in :attr:`Stats.notes`.
- Encoder settings are tried in :func:`plan_output`, before any input is opened
  (:mod:`marblevideo.media.encoders`); the encoder libraries' own log lines are off
  unless ``verbose``.
- Decode, transform and encode run in three threads joined by bounded queues
  (``QUEUE_FRAMES`` frames each), so memory stays flat; the transform runs in
  the calling thread. An error in any stage stops the others and is re-raised;
  KeyboardInterrupt propagates after cleanup. Output goes through
  :func:`marblevideo.output.atomic_output`: nothing is left on failure.
"""

from __future__ import annotations

import io
import os
import queue
import sys
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.media.encoders import (
    check_encoder,
    library_logs,
    option_table,
    quiet_environment,
    quiet_options,
)
from marblevideo.media.inputs import check_input
from marblevideo.media.output import atomic_output, check_output
from marblevideo.media.progress import MODES, Progress, progress_mode
from marblevideo.media.yuv import FORMATS, YuvMatrix, packed_i420, split_i420

Transform = Callable[[np.ndarray, float], np.ndarray]  # optional i420, i420_start, rgba_start

QUEUE_FRAMES = 4
AUDIO_MODES = ("copy", "aac", "none")

# extension -> (FFmpeg muxer, default video encoder, audio re-encoder)
CONTAINERS = {
    ".mp4": ("mp4", "libx264", "aac"),
    ".mov": ("mov", "libx264", "aac"),
    ".mkv": ("matroska", "libx264", "aac"),
    ".webm": ("webm", "libvpx-vp9", "libopus"),
}
# encoder -> its defaults, as ffmpeg's (VP9: constant quality needs b=0)
ENCODER_DEFAULTS = {
    "libx264": {"crf": "23", "preset": "medium"},
    "libx265": {"crf": "28", "preset": "medium"},
    "libvpx-vp9": {"crf": "31", "b": "0", "row-mt": "1"},
}
PRESET_CODECS = ("libx264", "libx265")
_COLOR_FIELDS = ("color_range", "colorspace", "color_primaries", "color_trc")


@dataclass
class VideoOptions:
    """Options of a video job; the fields mirror the command line's flags."""

    codec: str | None = None  # --codec: encoder name; default from the extension
    crf: int | None = None  # --crf: constant quality (x264 23, x265 28, VP9 31)
    preset: str | None = None  # --preset: x264/x265 speed preset (medium)
    pix_fmt: str = "yuv420p"  # --pix-fmt
    encoder_opts: dict[str, str] = field(default_factory=dict)  # --encoder-opt KEY=VALUE
    audio: str = "copy"  # --audio copy|aac|none
    start: float | None = None  # --start: seconds on the input's clock
    end: float | None = None  # --end: seconds on the input's clock (exclusive)
    size: tuple[int, int] | None = None  # --size W H: what the transform produces
    overwrite: bool = False  # -y
    quiet: bool = False  # --quiet: no progress bar, no notices on stderr
    progress: str = "auto"  # --progress auto|bar|json|off
    notify: Callable[[str], None] | None = None  # one-line notices; default stderr
    verbose: bool = False  # --verbose: the encoder libraries' and FFmpeg's own log lines


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
class OutputPlan:
    """Validated output settings (:func:`plan_output`), used by :class:`Encoder`."""

    format: str
    codec: str
    pix_fmt: str
    codec_options: dict[str, str]
    container_options: dict[str, str]
    audio_encoder: str
    supported: set[str]
    even: tuple[bool, bool]  # width, height must be even


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

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width) of the frame."""
        if self.i420 is not None:
            return split_i420(self.i420)[0].shape
        return self.rgba.shape[:2]


@dataclass
class _Audio:
    index: int  # input stream index
    payload: av.Packet | av.AudioFrame  # packet to copy or frame to encode


_END = object()


class _Stopped(Exception):
    """Raised inside a stage when another stage stopped the pipeline."""


# ---------------------------------------------------------------------------- validation


def _say(options: VideoOptions, stats: Stats, message: str) -> None:
    stats.notes.append(message)
    if options.notify is not None:
        options.notify(message)
    elif not options.quiet:
        print(f"marblevideo: {message}", file=sys.stderr, flush=True)


def plan_output(dst: str | os.PathLike, options: VideoOptions) -> OutputPlan:
    """Check every output setting before anything is opened; UsageError on a bad one."""
    ext = Path(dst).suffix.lower()
    if ext not in CONTAINERS:
        known = ", ".join(CONTAINERS)
        raise UsageError(f"{dst}: unknown output extension {ext or '(none)'!r}; use one of {known}")
    fmt, default_codec, audio_encoder = CONTAINERS[ext]
    name = options.codec or default_codec
    try:
        codec = av.Codec(name, "w")
    except (ValueError, av.error.FFmpegError):
        raise UsageError(f"unknown video encoder {name!r}") from None
    if codec.type != "video":
        raise UsageError(f"{name!r} is not a video encoder")
    with av.open(io.BytesIO(), "w", format=fmt) as probe:
        supported = set(probe.supported_codecs)
    if codec.canonical_name not in supported and codec.name not in supported:
        raise UsageError(f"{ext} files cannot hold {codec.canonical_name} video ({name})")
    try:
        pix = av.VideoFormat(options.pix_fmt)
    except (ValueError, av.error.FFmpegError):
        raise UsageError(f"unknown pixel format {options.pix_fmt!r}") from None
    formats = [f.name for f in codec.video_formats or ()]
    if formats and options.pix_fmt not in formats:
        raise UsageError(f"{name} cannot encode {options.pix_fmt}; it takes {', '.join(formats)}")
    table = option_table(name)
    has_preset = name in PRESET_CODECS if table is None else "preset" in table
    if options.preset is not None and not has_preset:
        raise UsageError(f"--preset: {name} has no presets; use --encoder-opt")
    if options.audio not in AUDIO_MODES:
        raise UsageError(f"audio must be one of {', '.join(AUDIO_MODES)}, got {options.audio!r}")
    if options.audio == "aac" and "aac" not in supported:
        raise UsageError(f"{ext} files cannot hold AAC audio; use audio copy (re-encodes) or none")
    if options.progress not in MODES:
        raise UsageError(f"progress must be one of {', '.join(MODES)}, got {options.progress!r}")
    _check_range(options.start, options.end)
    if options.size is not None and (len(options.size) != 2 or min(options.size) < 1):
        raise UsageError(f"size must be two positive integers, got {options.size!r}")
    codec_options = dict(ENCODER_DEFAULTS.get(name, {}))
    given: dict[str, tuple[str, str]] = {}  # option -> (the flag that set it, its value)
    if options.crf is not None:
        given["crf"] = ("--crf", str(options.crf))
    if options.preset is not None:
        given["preset"] = ("--preset", options.preset)
    for key, value in options.encoder_opts.items():
        given[str(key)] = ("--encoder-opt", str(value))
    codec_options.update({key: value for key, (_, value) in given.items()})
    codec_options = quiet_options(name, codec_options, options.verbose)
    quiet_environment(name, options.verbose)  # before the probe: SVT-AV1 reads it once
    check_encoder(name, options.pix_fmt, codec_options, given, table)
    container_options = {"movflags": "+faststart"} if fmt in ("mp4", "mov") else {}
    even = (pix.chroma_width(2) < 2, pix.chroma_height(2) < 2)
    return OutputPlan(
        fmt, name, options.pix_fmt, codec_options, container_options, audio_encoder, supported, even
    )


def _check_range(start: float | None, end: float | None) -> None:
    if start is not None and start < 0:
        raise UsageError(f"start must be >= 0 seconds, got {start}")
    if end is not None and end <= (start or 0):
        raise UsageError(f"end ({end} s) must be after start ({start or 0} s)")


# ---------------------------------------------------------------------------- decoding


def _open_input(src: str | os.PathLike) -> av.container.InputContainer:
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


def _planes(frame: av.VideoFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The I420 planes (y, u, v) of a yuv420p frame: views of its buffers, which
    they keep alive (no copy; rows padded to the frame's line sizes)."""
    return tuple(
        np.frombuffer(plane, np.uint8).reshape(-1, plane.line_size)[: plane.height, : plane.width]
        for plane in frame.planes
    )


def _frame_of(array: np.ndarray, format: str, height: int) -> av.VideoFrame:
    """A frame of ``height`` rows on ``array``'s own memory (PyAV's
    ``from_numpy_buffer``, which keeps it alive), or a copy where this PyAV cannot
    wrap it (PyAV 18 takes a yuv420p height that is not a multiple of 4 for the
    multiple of 4 below it)."""
    try:
        frame = av.VideoFrame.from_numpy_buffer(array, format=format)
        if frame.height == height:
            return frame
    except (AttributeError, ValueError):
        pass
    return av.VideoFrame.from_ndarray(array, format=format)


def _upright(frame: av.VideoFrame) -> np.ndarray:
    """The frame as the viewer sees it: RGBA, display rotation applied, C-contiguous."""
    rgba = frame.to_ndarray(
        format="rgba", src_colorspace=frame.colorspace, src_color_range=frame.color_range
    )
    turns = round(frame.rotation / 90) % 4  # counter-clockwise quarter turns
    return np.ascontiguousarray(np.rot90(rgba, turns) if turns else rgba)


class _Reader:
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

    def items(self) -> Iterator[VideoItem | _Audio]:
        """Yield video and audio items in demux order (audio held until the origin is known)."""
        if self.start:
            target = self.clock + int(self.start / self.tb)
            self.container.seek(target, stream=self.video, backward=True, any_frame=False)
        streams = [self.video] + [self.container.streams[i] for i in self.audio]
        for stream in streams[1:]:
            if self.audio[stream.index] != "copy":
                stream.thread_type = "AUTO"
        held: list[_Audio] = []
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
                    item = _Audio(index, payload)
                    keep = self._audio_in_range(item)
                    if keep is None:
                        done[index] = True
                        break
                    if self.origin is None:
                        held.append(item)
                    elif keep:
                        yield self._shifted(item)

    def _audio_in_range(self, item: _Audio) -> bool | None:
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
                return VideoItem(None, pts, frame.duration or 0, t, _planes(frame), matrix)
        return VideoItem(_upright(frame), pts, frame.duration or 0, t)

    def _shifted(self, item: _Audio) -> _Audio:
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


def _estimate_frames(reader: _Reader) -> int | None:
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


# ---------------------------------------------------------------------------- encoding


class Encoder:
    """Owns an open output container: :meth:`open_video` (then :meth:`open_audio`)
    adds the streams, :meth:`video` and :meth:`audio` encode and mux items,
    :meth:`flush` drains the encoders. ``say`` takes one-line notices
    (:func:`notifier`). Used by the file pipeline and by live recording."""

    def __init__(self, out, plan: OutputPlan, options: VideoOptions, stats: Stats, say):
        self.out, self.plan, self.options, self.stats, self.say = out, plan, options, stats, say
        self.stream = None
        self.shape: tuple[int, int] | None = None
        self.pad = (0, 0)
        self.colors: dict[str, int] = {}
        self.audio_out: dict[int, av.stream.Stream] = {}
        self.held: list[_Audio] = []  # audio that arrived before the first frame
        self.span: list[int] = []  # first pts, last pts, end of the last frame

    def open_video(self, width: int, height: int, time_base: Fraction, rate, colors: dict) -> None:
        """Add the video stream (then the audio ones, so video is stream 0)."""
        if self.options.size is not None and (width, height) != tuple(self.options.size):
            raise ValueError(f"transform gave {width}x{height}, size option is {self.options.size}")
        pad_w = width % 2 if self.plan.even[0] else 0
        pad_h = height % 2 if self.plan.even[1] else 0
        if pad_w or pad_h:
            self.say(
                f"{width}x{height} padded to {width + pad_w}x{height + pad_h} "
                f"(edge pixels repeated): {self.plan.pix_fmt} needs even sizes"
            )
        self.shape, self.pad = (height, width), (pad_h, pad_w)
        stream = self.out.add_stream(self.plan.codec, rate=rate)
        ctx = stream.codec_context
        ctx.width, ctx.height, ctx.pix_fmt = width + pad_w, height + pad_h, self.plan.pix_fmt
        ctx.time_base = stream.time_base = time_base
        ctx.thread_type = "AUTO"
        ctx.options = dict(self.plan.codec_options)
        self.colors = {k: v for k, v in colors.items() if v}
        for key, value in self.colors.items():
            setattr(ctx, key, value)
        self.stream = stream
        self.stats.size = (ctx.width, ctx.height)

    def open_audio(self, sources: dict[int, tuple[av.stream.Stream, str]]) -> None:
        for index, (template, how) in sources.items():
            if how == "copy":
                self.audio_out[index] = self.out.add_stream_from_template(template)
                continue
            codec = av.Codec(how, "w")
            rate = template.rate
            if codec.audio_rates and rate not in codec.audio_rates:
                rate = 48000 if 48000 in codec.audio_rates else codec.audio_rates[0]
            stream = self.out.add_stream(how, rate=rate)
            stream.layout = template.layout.name
            stream.format = codec.audio_formats[0].name
            self.audio_out[index] = stream

    def video(self, item: VideoItem) -> None:
        if item.shape != self.shape:
            raise ValueError(f"transform changed frame size: {item.shape} after {self.shape}")
        if item.i420 is not None:
            frame = _frame_of(packed_i420(item.i420), "yuv420p", self.shape[0])
            self.stats.i420_frames += 1
        else:
            rgba = item.rgba
            if any(self.pad):
                rgba = np.pad(rgba, ((0, self.pad[0]), (0, self.pad[1]), (0, 0)), mode="edge")
            frame = _frame_of(rgba, "rgba", rgba.shape[0])
            frame = frame.reformat(
                format=self.plan.pix_fmt,
                dst_colorspace=self.colors.get("colorspace"),
                dst_color_range=self.colors.get("color_range"),
            )
        for key, value in self.colors.items():
            setattr(frame, key, value)
        frame.pts, frame.time_base = item.pts, self.stream.codec_context.time_base
        if item.duration:
            frame.duration = item.duration
        self.out.mux(self.stream.encode(frame))
        self.stats.frames += 1
        self._extend(item)

    def _extend(self, item: VideoItem) -> None:
        """Track the span of the frames written (a frame without a duration lasts
        as long as the gap before it)."""
        if not self.span:
            self.span = [item.pts, item.pts, item.pts + item.duration]
            return
        step = item.duration or item.pts - self.span[1]
        self.span[1:] = [item.pts, max(self.span[2], item.pts + step)]

    def audio(self, item: _Audio) -> None:
        stream = self.audio_out[item.index]
        payload = item.payload
        if isinstance(payload, av.Packet):
            payload.stream = stream
            self.out.mux(payload)
            self.stats.audio_packets += 1
        else:
            packets = stream.encode(payload)
            self.out.mux(packets)
            self.stats.audio_packets += len(packets)

    def flush(self) -> None:
        if self.stream is not None:
            self.out.mux(self.stream.encode(None))
        if self.span:
            time_base = self.stream.codec_context.time_base
            self.stats.duration = float((self.span[2] - self.span[0]) * time_base)
        for stream in self.audio_out.values():
            if stream.codec_context.is_encoder:
                packets = stream.encode(None)
                self.out.mux(packets)
                self.stats.audio_packets += len(packets)


# ---------------------------------------------------------------------------- pipeline


class _Pipeline:
    """Stage threads joined by bounded queues; the first error stops them all."""

    POLL = 0.1

    def __init__(self):
        self.stop = threading.Event()
        self.error: BaseException | None = None
        self.threads: list[threading.Thread] = []

    def put(self, q: queue.Queue, item) -> None:
        while True:
            if self.stop.is_set():
                raise _Stopped
            try:
                q.put(item, timeout=self.POLL)
                return
            except queue.Full:
                pass

    def get(self, q: queue.Queue):
        while True:
            if self.stop.is_set() and q.empty():
                raise _Stopped
            try:
                return q.get(timeout=self.POLL)
            except queue.Empty:
                pass

    def start(self, name: str, target: Callable[[], None]) -> None:
        def run():
            try:
                target()
            except _Stopped:
                pass
            except BaseException as exc:  # noqa: BLE001 - handed to the caller
                if self.error is None:
                    self.error = exc
                self.stop.set()

        thread = threading.Thread(target=run, name=f"marblevideo-{name}", daemon=True)
        self.threads.append(thread)
        thread.start()

    def join(self, timeout: float = 10.0) -> None:
        for thread in self.threads:
            thread.join(timeout)


def _check_i420(planes):
    try:
        split_i420(planes)
    except ValueError as exc:
        raise ValueError(f"transform.i420 returned no I420 frame: {exc}") from None
    return planes


def _started(finish, kind: str) -> Callable[[], object]:
    if not callable(finish):
        raise TypeError(f"transform.{kind}_start must return a function")
    return finish


def _check_frame(rgba) -> np.ndarray:
    if not isinstance(rgba, np.ndarray) or rgba.dtype != np.uint8 or rgba.ndim != 3:
        raise TypeError("transform must return an (h, w, 4) uint8 numpy array")
    if rgba.shape[2] != 4:
        raise ValueError(f"transform must return 4 channels (RGBA), got shape {rgba.shape}")
    return np.ascontiguousarray(rgba)


def _run(
    out_path: Path,
    plan: OutputPlan,
    options: VideoOptions,
    stats: Stats,
    produce: Callable[[], Iterator[VideoItem | _Audio]],
    transform: Callable[[VideoItem], Callable[[], None] | None],
    setup: Callable[[Encoder, VideoItem], None],
    total: int | None,
) -> None:
    """Decode (``produce``) -> transform (this thread, in place) -> encode, with bounded
    queues. ``transform`` may return a function that finishes the item: it is
    called once the next frame has been started (one frame in flight)."""
    pipe = _Pipeline()
    decoded: queue.Queue = queue.Queue(QUEUE_FRAMES)
    marbled: queue.Queue = queue.Queue(QUEUE_FRAMES)

    def decode():
        for item in produce():
            pipe.put(decoded, item)
        pipe.put(decoded, _END)

    out = av.open(str(out_path), "w", format=plan.format, options=plan.container_options)
    writer = Encoder(out, plan, options, stats, notifier(options, stats))

    def encode():
        try:
            while (item := pipe.get(marbled)) is not _END:
                if isinstance(item, VideoItem):
                    if writer.stream is None:
                        setup(writer, item)
                        for held in writer.held:
                            writer.audio(held)
                    writer.video(item)
                elif writer.stream is None:
                    writer.held.append(item)  # audio before the first frame
                else:
                    writer.audio(item)
            if writer.stream is None:
                raise MediaError("no video frames to write (check start and end)")
            writer.flush()
        except av.error.FFmpegError as exc:
            raise MediaError(f"{plan.codec} encoding failed: {exc.strerror}") from None

    ok = False
    try:
        with Progress(total, mode=progress_mode(options.progress, options.quiet)) as bar:
            pipe.start("decode", decode)
            pipe.start("encode", encode)
            flight: list = []  # (item, finish or None), in order; one frame among them

            def land() -> None:
                for item, finish in flight:
                    if finish is not None:
                        finish()
                    if isinstance(item, VideoItem):
                        bar.update()
                    pipe.put(marbled, item)
                flight.clear()

            while (item := pipe.get(decoded)) is not _END:
                finish = None
                if isinstance(item, VideoItem):
                    finish = transform(item)  # started: now the frame before can land
                    land()
                flight.append((item, finish))
            land()
            pipe.put(marbled, _END)
            for thread in pipe.threads:
                while thread.is_alive():  # short joins keep Ctrl-C responsive
                    thread.join(pipe.POLL)
            ok = pipe.error is None
    except _Stopped:
        pass  # a stage failed: its error is raised below
    finally:
        pipe.stop.set()
        pipe.join()
        try:
            out.close()
        except av.error.FFmpegError as exc:
            if ok:
                raise MediaError(f"cannot finish the output: {exc.strerror}") from None
    if pipe.error is not None:
        raise pipe.error


def notifier(options: VideoOptions, stats: Stats) -> Callable[[str], None]:
    """The one-line notice function of a job: ``options.notify`` or stderr, noted in
    ``stats``."""
    return lambda message: _say(options, stats, message)


# ---------------------------------------------------------------------------- public API


def transcode(
    src: str | os.PathLike,
    dst: str | os.PathLike,
    transform: Transform,
    options: VideoOptions | None = None,
    *,
    plan: OutputPlan | None = None,
) -> Stats:
    """Write ``dst``: every frame of ``src`` (in ``start``..``end``) through ``transform``.

    Raises UsageError (bad options, output = input), OutputExistsError,
    MediaError (unreadable input, encoder failure); exceptions from
    ``transform`` and KeyboardInterrupt propagate, leaving no output file.
    ``plan`` is :func:`plan_output`'s for ``dst`` and ``options``, where the
    caller has checked them already.
    """
    options = options or VideoOptions()
    began = time.monotonic()
    plan = plan or plan_output(dst, options)
    check_output(dst, options.overwrite, [src])
    stats = Stats()
    with _open_input(src) as container:
        say = notifier(options, stats)
        audio = _audio_plan(container, plan, options, Path(dst).suffix, say)
        encoders = set(audio.values()) - {"copy"}
        stats.audio = encoders.pop() if encoders else "copy" if audio else "none"
        vin = container.streams.video[0]
        colors = {k: getattr(vin.codec_context, k) for k in _COLOR_FIELDS}
        planar = getattr(transform, "i420", None)
        out_matrix = YuvMatrix.of(colors["colorspace"], colors["color_range"])
        if plan.pix_fmt != "yuv420p" or (options.size and any(v % 2 for v in options.size)):
            out_matrix = None
        reader = _Reader(
            container,
            options.start,
            options.end,
            audio,
            planar is not None and out_matrix is not None,
        )

        start = getattr(transform, "i420_start", None) if planar is not None else None
        rgba_start = getattr(transform, "rgba_start", None)

        def marble(item: VideoItem) -> Callable[[], None] | None:
            if item.i420 is not None:
                if start is None:
                    item.i420 = _check_i420(planar(item.i420, item.t, item.matrix, out_matrix))
                    return None
                started = _started(start(item.i420, item.t, item.matrix, out_matrix), "i420")
                return lambda: setattr(item, "i420", _check_i420(started()))
            if rgba_start is None:
                item.rgba = _check_frame(transform(item.rgba, item.t))
                return None
            started = _started(rgba_start(item.rgba, item.t), "rgba")
            return lambda: setattr(item, "rgba", _check_frame(started()))

        def setup(writer: Encoder, first: VideoItem) -> None:
            height, width = first.shape
            rate = vin.average_rate or vin.guessed_rate
            writer.open_video(width, height, vin.time_base, rate, colors)
            writer.open_audio({i: (container.streams[i], how) for i, how in audio.items()})

        with atomic_output(dst, options.overwrite, [src]) as tmp, library_logs(options.verbose):
            _run(
                tmp,
                plan,
                options,
                stats,
                reader.items,
                marble,
                setup,
                _estimate_frames(reader),
            )
        if reader.rotation:
            say(f"input rotated {reader.rotation} degrees: frames turned upright")
        stats.corrupt_packets = reader.corrupt
        if reader.corrupt:
            say(f"{src}: skipped {reader.corrupt} corrupt packet(s)")
    stats.seconds = time.monotonic() - began
    return stats


def _audio_plan(
    container, plan: OutputPlan, options: VideoOptions, ext: str, say
) -> dict[int, str]:
    """Input audio stream index -> "copy" or the encoder to re-encode it with."""
    if options.audio == "none":
        return {}
    audio = {}
    for stream in container.streams.audio:
        name = stream.codec_context.name
        if options.audio == "copy" and name in plan.supported:
            audio[stream.index] = "copy"
        else:
            if options.audio == "copy":
                say(f"{ext} files cannot hold {name} audio: re-encoding it to {plan.audio_encoder}")
            audio[stream.index] = plan.audio_encoder
    return audio


def iter_frames(
    src: str | os.PathLike, transform: Transform | None = None, options: VideoOptions | None = None
) -> Iterator[tuple[float, np.ndarray]]:
    """Yield ``(t, rgba)`` for each upright frame of ``src`` in ``start``..``end``,
    through ``transform`` when given. Only ``start``/``end``/``notify`` of ``options`` apply."""
    options = options or VideoOptions()
    _check_range(options.start, options.end)
    stats = Stats()
    with _open_input(src) as container:
        reader = _Reader(container, options.start, options.end, {})
        for item in reader.items():
            rgba = item.rgba if transform is None else _check_frame(transform(item.rgba, item.t))
            yield item.t, rgba
        if reader.corrupt:
            _say(options, stats, f"{src}: skipped {reader.corrupt} corrupt packet(s)")


def render_blank(
    dst: str | os.PathLike,
    render_at: Callable[[float], np.ndarray],
    duration: float,
    fps: float,
    options: VideoOptions | None = None,
    *,
    plan: OutputPlan | None = None,
) -> Stats:
    """Write ``dst`` from frames ``render_at(i / fps)``, ``i = 0 .. ceil(duration * fps) - 1``.

    Constant frame rate (time base 1/fps for integer rates), no audio, colours
    untagged (BT.601, limited range). For a yuv420p output, ``render_at.i420(t,
    matrix)``, where present, gives the frame as I420 in ``matrix`` (None where
    it cannot, e.g. odd sizes) and swscale is skipped; ``render_at.i420_start(t,
    matrix)``, where present, is used instead: it returns a function giving that
    frame (or None where it cannot), called once the next frame is started.
    ``plan`` as for :func:`transcode`.
    """
    options = options or VideoOptions()
    if duration <= 0 or fps <= 0:
        raise UsageError(f"duration and fps must be positive, got {duration} s at {fps} fps")
    began = time.monotonic()
    plan = plan or plan_output(dst, options)
    stats = Stats()
    rate = Fraction(fps).limit_denominator(1001)
    count = int(np.ceil(duration * fps - 1e-9))
    planar = getattr(render_at, "i420", None) if plan.pix_fmt == "yuv420p" else None
    start = getattr(render_at, "i420_start", None) if planar is not None else None
    matrix = YuvMatrix.of(None, None)

    def produce() -> Iterator[VideoItem]:
        return (VideoItem(None, i, 1, i / fps) for i in range(count))

    def render(item: VideoItem) -> Callable[[], None] | None:
        if start is not None:
            started = start(item.t, matrix)
            if started is not None:
                started = _started(started, "i420")
                return lambda: setattr(item, "i420", _check_i420(started()))
        planes = None if planar is None or start is not None else planar(item.t, matrix)
        if planes is not None:
            item.i420 = _check_i420(planes)
        else:
            item.rgba = _check_frame(render_at(item.t))
        return None

    def setup(writer: Encoder, first: VideoItem) -> None:
        height, width = first.shape
        writer.open_video(width, height, 1 / rate, rate, {})

    with atomic_output(dst, options.overwrite) as tmp, library_logs(options.verbose):
        _run(tmp, plan, options, stats, produce, render, setup, count)
    stats.seconds = time.monotonic() - began
    return stats
