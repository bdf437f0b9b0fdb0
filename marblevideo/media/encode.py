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
from marblevideo.media.formats import (
    FORMATS,
    is_sequence,
    is_stdio,
    output_format,
    output_kinds,
)
from marblevideo.media.output import refuse_folder
from marblevideo.media.palette import PaletteFrames
from marblevideo.media.progress import MODES
from marblevideo.media.scheduling import ordinary_scheduling
from marblevideo.media.video import (
    AUDIO_MODES,
    AudioItem,
    Span,
    Stats,
    VideoItem,
    VideoOptions,
    check_range,
)
from marblevideo.media.yuv import packed_i420

# encoder -> its defaults, as ffmpeg's (VP9: constant quality needs b=0)
ENCODER_DEFAULTS = {
    "libx264": {"crf": "23", "preset": "medium"},
    "libx265": {"crf": "28", "preset": "medium"},
    "libvpx-vp9": {"crf": "31", "b": "0", "row-mt": "1"},
}
PRESET_CODECS = ("libx264", "libx265")
COLOR_FIELDS = ("color_range", "colorspace", "color_primaries", "color_trc")


def default_codec(dst: str | os.PathLike, forced: str | None = None) -> str | None:
    """The video encoder an output gets by default (None: no video format)."""
    name = output_format(dst, forced)
    return None if name is None else FORMATS[name].codec


@dataclass
class OutputPlan:
    """Validated output settings (:func:`plan_output`), used by the writers
    (:mod:`marblevideo.media.sinks`). ``format`` is the FFmpeg muxer (``image2``
    for an image sequence, which OpenCV writes); ``audio_encoder`` None: the
    output holds no audio; ``palette``: a GIF palette computed for the clip;
    ``stream``: written to standard output."""

    format: str
    codec: str
    pix_fmt: str
    codec_options: dict[str, str]
    container_options: dict[str, str]
    audio_encoder: str | None
    supported: set[str]
    even: tuple[bool, bool]  # width, height must be even
    sequence: bool = False
    palette: bool = False
    stream: bool = False


def plan_output(dst: str | os.PathLike, options: VideoOptions) -> OutputPlan:
    """Check every output setting before anything is opened; UsageError on a bad one."""
    _check_options(options)
    if is_sequence(dst) and options.format is None:
        return _sequence_plan(dst, options)
    name = _format_name(dst, options)
    fmt = FORMATS[name]
    codec_name = options.codec or fmt.codec
    codec, supported = _video_codec(name, fmt, codec_name)
    pix_fmt = options.pix_fmt or (fmt.pix_fmt if codec_name == fmt.codec else "yuv420p")
    pix = _pixel_format(codec, codec_name, pix_fmt)
    table = option_table(codec_name)
    has_preset = codec_name in PRESET_CODECS if table is None else "preset" in table
    if options.preset is not None and not has_preset:
        raise UsageError(f"--preset: {codec_name} has no presets; use --encoder-opt")
    if options.audio == "aac" and (fmt.audio is None or "aac" not in supported):
        raise UsageError(f"--audio aac: {name} cannot hold AAC audio; use copy or none")
    codec_options = _codec_options(codec_name, pix_fmt, options, table)
    stream = is_stdio(dst)
    palette = codec_name == "gif"
    even = (pix.chroma_width(2) < 2, pix.chroma_height(2) < 2) if not palette else (False, False)
    return OutputPlan(
        fmt.muxer,
        codec_name,
        pix_fmt,
        codec_options,
        dict(fmt.stream_options if stream else fmt.file_options),
        fmt.audio,
        supported,
        even,
        palette=palette,
        stream=stream,
    )


def _check_options(options: VideoOptions) -> None:
    """The options that need no output: range, audio mode, progress mode, size."""
    check_range(options.start, options.end)
    if options.audio not in AUDIO_MODES:
        raise UsageError(f"audio must be one of {', '.join(AUDIO_MODES)}, got {options.audio!r}")
    if options.progress not in MODES:
        raise UsageError(f"progress must be one of {', '.join(MODES)}, got {options.progress!r}")
    if options.size is not None and (len(options.size) != 2 or min(options.size) < 1):
        raise UsageError(f"size must be two positive integers, got {options.size!r}")


def _format_name(dst: str | os.PathLike, options: VideoOptions) -> str:
    """The output's format (a key of FORMATS), by ``--format`` or the extension."""
    name = output_format(dst, options.format)
    if name is not None:
        return name
    if is_stdio(dst):
        raise UsageError("-o -: name the stream's format with --format (e.g. matroska, nut)")
    refuse_folder(dst)  # before its extension (it has none) is blamed
    ext = Path(dst).suffix.lower()
    raise UsageError(f"{dst}: unknown output extension {ext or '(none)'!r}; use {output_kinds()}")


def _video_codec(name: str, fmt, codec_name: str) -> tuple[av.Codec, set[str]]:
    """(the video encoder ``codec_name``, the codecs the format's muxer holds)."""
    try:
        codec = av.Codec(codec_name, "w")
    except (ValueError, av.error.FFmpegError):
        raise UsageError(f"unknown video encoder {codec_name!r}") from None
    if codec.type != "video":
        raise UsageError(f"{codec_name!r} is not a video encoder")
    with av.open(io.BytesIO(), "w", format=fmt.muxer) as probe:
        supported = set(probe.supported_codecs) | fmt.also_holds
    if codec.canonical_name not in supported and codec.name not in supported:
        raise UsageError(f"{name} cannot hold {codec.canonical_name} video ({codec_name})")
    return codec, supported


def _pixel_format(codec: av.Codec, codec_name: str, pix_fmt: str) -> av.VideoFormat:
    try:
        pix = av.VideoFormat(pix_fmt)
    except (ValueError, av.error.FFmpegError):
        raise UsageError(f"unknown pixel format {pix_fmt!r}") from None
    formats = [f.name for f in codec.video_formats or ()]
    if formats and pix_fmt not in formats:
        raise UsageError(f"{codec_name} cannot encode {pix_fmt}; it takes {', '.join(formats)}")
    return pix


def _codec_options(codec_name: str, pix_fmt: str, options: VideoOptions, table) -> dict:
    """The encoder's options: its defaults, then --crf, --preset, --encoder-opt,
    tried on the encoder (:func:`~marblevideo.media.encoders.check_encoder`)."""
    codec_options = dict(ENCODER_DEFAULTS.get(codec_name, {}))
    given: dict[str, tuple[str, str]] = {}  # option -> (the flag that set it, its value)
    if options.crf is not None:
        given["crf"] = ("--crf", str(options.crf))
    if options.preset is not None:
        given["preset"] = ("--preset", options.preset)
    for key, value in options.encoder_opts.items():
        given[str(key)] = ("--encoder-opt", str(value))
    codec_options.update({key: value for key, (_, value) in given.items()})
    codec_options = quiet_options(codec_name, codec_options, options.verbose)
    quiet_environment(codec_name, options.verbose)  # before the probe: SVT-AV1 reads it once
    check_encoder(codec_name, pix_fmt, codec_options, given, table)
    return codec_options


def _sequence_plan(dst: str | os.PathLike, options: VideoOptions) -> OutputPlan:
    """An image sequence: OpenCV writes each frame as a still (no encoder settings)."""
    for flag, value in (
        ("--codec", options.codec),
        ("--crf", options.crf),
        ("--preset", options.preset),
        ("--pix-fmt", options.pix_fmt),
        ("--encoder-opt", options.encoder_opts or None),
    ):
        if value is not None:
            raise UsageError(f"{flag}: {dst} is an image sequence, written as stills")
    if options.audio == "aac":
        raise UsageError(f"--audio aac: {dst} is an image sequence, which holds no audio")
    return OutputPlan("image2", "", "rgb24", {}, {}, None, set(), (False, False), sequence=True)


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
    :meth:`flush` drains the encoders. ``notify`` takes one-line notices
    (:func:`job_notify`). Used by the file pipeline and by live recording."""

    def __init__(self, out, plan: OutputPlan, options: VideoOptions, stats: Stats, notify):
        self.out, self.plan, self.options, self.stats, self.notify = (
            out,
            plan,
            options,
            stats,
            notify,
        )
        self.stream = None
        self.shape: tuple[int, int] | None = None
        self.pad = (0, 0)
        self.colors: dict[str, int] = {}
        self.audio_out: dict[int, av.stream.Stream] = {}
        self.held: list[AudioItem] = []  # audio that arrived before the first frame
        self.span = Span()
        self.palette: PaletteFrames | None = None  # GIF: frames wait for the clip's palette

    def open_video(self, width: int, height: int, time_base: Fraction, rate, colors: dict) -> None:
        """Add the video stream (then the audio ones, so video is stream 0)."""
        if self.options.size is not None and (width, height) != tuple(self.options.size):
            raise ValueError(f"transform gave {width}x{height}, size option is {self.options.size}")
        pad_w = width % 2 if self.plan.even[0] else 0
        pad_h = height % 2 if self.plan.even[1] else 0
        if pad_w or pad_h:
            self.notify(
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
        if self.plan.palette:
            self.palette = PaletteFrames(ctx.width, ctx.height, time_base)

    def open_audio(self, sources: dict[int, tuple[av.stream.Stream, str]]) -> None:
        for index, (template, how) in sources.items():
            if how == "copy":
                stream = self.out.add_stream_from_template(template)
                if stream.layout.name != _ordered(template.layout):
                    stream.layout = _ordered(template.layout)  # MP4 refuses "2 channels"
                self.audio_out[index] = stream
                continue
            codec = av.Codec(how, "w")
            rate = template.rate
            if codec.audio_rates and rate not in codec.audio_rates:
                rate = 48000 if 48000 in codec.audio_rates else codec.audio_rates[0]
            stream = self.out.add_stream(how, rate=rate)
            stream.layout = _ordered(template.layout)
            stream.format = codec.audio_formats[0].name
            self.audio_out[index] = stream

    def video(self, item: VideoItem) -> None:
        if item.shape != self.shape:
            raise ValueError(f"transform changed frame size: {item.shape} after {self.shape}")
        if self.palette is not None:
            self.palette.add(item.rgba, item.pts, item.duration)
            self.stats.frames += 1
            self.span.extend(item)
            return
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
        if item.key:
            frame.pict_type = av.video.frame.PictureType.I
        if item.duration:
            frame.duration = item.duration
        if self.stream.codec_context.is_open:
            self.out.mux(self.stream.encode(frame))
        else:  # the first frame opens the encoder
            with ordinary_scheduling():
                self.out.mux(self.stream.encode(frame))
        self.stats.frames += 1
        self.span.extend(item)

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
        if self.palette is not None:
            self.palette.finish(lambda frame: self.out.mux(self.stream.encode(frame)))
        if self.stream is not None:
            with ordinary_scheduling():
                self.out.mux(self.stream.encode(None))
            self.stats.duration = self.span.seconds(self.stream.codec_context.time_base)
        for stream in self.audio_out.values():
            if stream.codec_context.is_encoder:
                packets = stream.encode(None)
                self.out.mux(packets)
                self.stats.audio_packets += len(packets)


#: The usual channel layout for a count of channels.
_LAYOUTS = {1: "mono", 2: "stereo", 3: "2.1", 4: "quad", 5: "5.0", 6: "5.1", 7: "6.1", 8: "7.1"}


def _ordered(layout: av.AudioLayout) -> str:
    """A layout an encoder opens with: an input's without a channel order ("2
    channels", as WAV and PCM in Matroska give) as the usual one of that count."""
    if layout.name.endswith("channels"):
        return _LAYOUTS.get(layout.nb_channels, layout.name)
    return layout.name


def audio_plan(
    container, plan: OutputPlan, options: VideoOptions, name: str, notify
) -> dict[int, str]:
    """Input audio stream index -> "copy" or the encoder to re-encode it with.
    ``name`` names the output in notices."""
    if options.audio == "none" or not container.streams.audio:
        return {}
    if plan.audio_encoder is None:
        what = "an image sequence" if plan.sequence else f"{plan.format} output"
        notify(f"{what} holds no audio: the input's audio is left out")
        return {}
    audio = {}
    for stream in container.streams.audio:
        codec = stream.codec_context.name
        if options.audio == "auto" and not plays_everywhere(plan.format, codec):
            notify(
                f"{codec} audio in {name} does not play everywhere (QuickTime, Safari): "
                f"re-encoding it to {plan.audio_encoder} (--audio copy keeps it)"
            )
            audio[stream.index] = plan.audio_encoder
        elif options.audio in ("copy", "auto") and codec in plan.supported:
            audio[stream.index] = "copy"
        else:
            if options.audio != "aac":
                notify(f"{name} cannot hold {codec} audio: re-encoding it to {plan.audio_encoder}")
            audio[stream.index] = plan.audio_encoder
    return audio


#: Audio that MP4 and MOV can hold but QuickTime and older Safari do not play.
NOT_EVERYWHERE = ("opus", "flac", "vorbis")


def plays_everywhere(muxer: str, codec: str) -> bool:
    """Whether ``codec`` audio in a ``muxer`` file plays in the common players: not
    Opus, FLAC, Vorbis or PCM in an MP4 or MOV (``--audio`` auto re-encodes those)."""
    if muxer not in ("mp4", "mov"):
        return True
    return codec not in NOT_EVERYWHERE and not codec.startswith("pcm_")
