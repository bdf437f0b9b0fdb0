"""Encoding: the output's settings checked before any work (:func:`plan_output`:
container, encoder and its options, pixel format, audio), and the
:class:`Encoder` that owns an open output container."""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

from marblevideo.errors import UsageError
from marblevideo.media.encoders import check_encoder, option_table, quiet_environment, quiet_options
from marblevideo.media.progress import MODES
from marblevideo.media.video import (
    AUDIO_MODES,
    AudioItem,
    Stats,
    VideoItem,
    VideoOptions,
    check_range,
)
from marblevideo.media.yuv import packed_i420

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
COLOR_FIELDS = ("color_range", "colorspace", "color_primaries", "color_trc")


def default_codec(dst: str | os.PathLike) -> str | None:
    """The video encoder an output's extension gets by default (None: unknown)."""
    container = CONTAINERS.get(Path(dst).suffix.lower())
    return None if container is None else container[1]


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
    check_range(options.start, options.end)
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


def frame_of(array: np.ndarray, format: str, height: int) -> av.VideoFrame:
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
        self.held: list[AudioItem] = []  # audio that arrived before the first frame
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
            frame = frame_of(packed_i420(item.i420), "yuv420p", self.shape[0])
            self.stats.i420_frames += 1
        else:
            rgba = item.rgba
            if any(self.pad):
                rgba = np.pad(rgba, ((0, self.pad[0]), (0, self.pad[1]), (0, 0)), mode="edge")
            frame = frame_of(rgba, "rgba", rgba.shape[0])
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

    def audio(self, item: AudioItem) -> None:
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


def audio_plan(container, plan: OutputPlan, options: VideoOptions, ext: str, say) -> dict[int, str]:
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
