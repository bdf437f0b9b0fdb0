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
- A transform may also be a :class:`~marblevideo.jobs.transforms.PipelinedTransform`
  (as :meth:`marblevideo.marbler.Marbler.transform`'s is): the pipeline keeps one
  frame in flight, starting frame n + 1 before it finishes frame n, so a device
  renders while the host prepares the next frame; and where it is ``planar`` it
  takes the frame as I420 planes ``(y, u, v)`` (:mod:`marblevideo.media.yuv`)
  with colours in the input's :class:`~marblevideo.media.yuv.YuvMatrix` and gives
  packed I420 in the output's. Which way frames go is the job's
  :class:`~marblevideo.jobs.route.Route`, decided once
  (:func:`~marblevideo.jobs.route.video_route`): I420 for every frame that is
  8-bit 4:2:0, upright and even-sized, with a supported matrix, when the output
  is yuv420p of even size. The marbler
  warps the planes themselves when the input and output matrices are the same
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
  (``QUEUE_FRAMES`` frames each; :mod:`marblevideo.jobs.stages`), so memory
  stays flat; the transform runs in the calling thread
  (:mod:`marblevideo.jobs.transforms`). An error in any stage stops the others and is re-raised;
  KeyboardInterrupt propagates after cleanup. Output goes through
  :func:`marblevideo.media.output.atomic_output`: nothing is left on failure.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from marblevideo.jobs.retime import rate_fraction, retimed
from marblevideo.jobs.route import sheet_route, video_route
from marblevideo.jobs.stages import Writer, run_stages
from marblevideo.jobs.transforms import (
    PipelinedSource,
    PipelinedTransform,
    SheetStage,
    TransformStage,
    check_frame,
    pipelined,
    sheet_source,
)
from marblevideo.media.decode import Reader, estimate_frames, open_input
from marblevideo.media.encode import COLOR_FIELDS, OutputPlan, audio_plan, plan_output
from marblevideo.media.encoders import library_logs
from marblevideo.media.inputs import Input, classify
from marblevideo.media.output import check_output
from marblevideo.media.progress import progress_mode
from marblevideo.media.sinks import video_writer
from marblevideo.media.soundtrack import opened
from marblevideo.media.video import (
    AudioItem,
    Stats,
    VideoItem,
    VideoOptions,
    check_range,
    job_notify,
    notify,
)

RgbaTransform = Callable[[np.ndarray, float], np.ndarray]
"""``transform(rgba, t) -> rgba``, or a
:class:`~marblevideo.jobs.transforms.PipelinedTransform` (see the module)."""


def transcode(
    src: str | os.PathLike | Input,
    dst: str | os.PathLike,
    transform: RgbaTransform | PipelinedTransform,
    options: VideoOptions | None = None,
    *,
    plan: OutputPlan | None = None,
    pts_origin: int | None = None,
) -> Stats:
    """Write ``dst``: every frame of ``src`` (in ``start``..``end``) through ``transform``.

    ``src`` is a file, an image sequence, ``-`` (standard input) or a URL, by
    name or classified (:class:`~marblevideo.media.inputs.Input`); ``dst`` a
    file, an image sequence or ``-`` (standard output, in ``options.format``).
    With ``options.fps`` the frame rate is converted (:mod:`marblevideo.jobs.retime`),
    or an image sequence read at it.

    Raises UsageError (bad options, output = input), OutputExistsError,
    MediaError (unreadable input, encoder failure); exceptions from
    ``transform`` and KeyboardInterrupt propagate, leaving no output file.
    ``plan``: :func:`plan_output`'s, where the caller has checked the options and
    output. ``pts_origin``: :class:`~marblevideo.media.decode.Reader`'s (segments).
    """
    transform, options = pipelined(transform), options or VideoOptions()
    began = time.monotonic()
    source = classify(src)
    if plan is None:
        plan = plan_output(dst, options)
        check_output(dst, options.overwrite, source.names)
    stats = Stats()
    with open_input(source, options.fps) as container, opened(options.soundtrack) as sound:
        notify = job_notify(options, stats)
        own, audio = _audio(container, sound, dst, plan, options, stats)
        vin = container.streams.video[0]
        colors = {k: getattr(vin.codec_context, k) for k in COLOR_FIELDS}
        route = video_route(transform, colors, plan, options.size)
        marble = TransformStage(transform, route, options.size, options.fit, notify)
        span = options.start, options.end
        reader = Reader(container, *span, own, route.planar, pts_origin, route.luma)
        clock = _Clock(vin, None if source.kind == "sequence" else options.fps)

        def produce() -> Iterator[VideoItem | AudioItem]:
            items = clock.retimed(reader.items())
            return items if sound is None else sound.mixed(items, clock.time_base)

        def setup(writer: Writer, first: VideoItem) -> None:
            height, width = first.shape
            writer.open_video(width, height, clock.time_base, clock.rate, colors)
            streams = container.streams if sound is None else {sound.stream.index: sound.stream}
            writer.open_audio({i: (streams[i], how) for i, how in audio.items()})

        total = estimate_frames(reader, clock.fps)
        with (
            video_writer(dst, plan, options, stats, source.names) as writer,
            library_logs(options.verbose),
        ):
            run_stages(writer, plan, _progress(options), produce, marble, setup, total)
        _tell_reader(reader, source.name, stats, notify)
    stats.seconds = time.monotonic() - began
    return stats


def _audio(container, sound, dst, plan: OutputPlan, options: VideoOptions, stats: Stats):
    """(the input's audio streams read: index -> "copy" or an encoder, the output's
    audio: the input's, else the soundtrack's), with ``stats.audio`` told."""
    notify = job_notify(options, stats)
    name = "standard output" if plan.stream else f"{Path(dst).suffix} files"
    own = audio_plan(container, plan, options, name, notify) if sound is None else {}
    audio = own or (sound.plan(plan, options, notify) if sound else {})
    encoders = set(audio.values()) - {"copy"}
    stats.audio = encoders.pop() if encoders else "copy" if audio else "none"
    return own, audio


def _progress(options: VideoOptions) -> str:
    return progress_mode(options.progress, options.quiet)


class _Clock:
    """The output's time base and rate: the input video stream's, or ``fps``'s
    when the frame rate is converted (None: kept)."""

    def __init__(self, vin, fps: float | None):
        self.vin, self.fps = vin, fps
        self.time_base, self.rate = vin.time_base, vin.average_rate or vin.guessed_rate
        if fps is not None:
            self.rate = rate_fraction(fps)
            self.time_base = 1 / self.rate

    def retimed(self, items: Iterator) -> Iterator:
        return items if self.fps is None else retimed(items, self.vin.time_base, self.fps)


def _tell_reader(reader: Reader, src, stats: Stats, notify) -> None:
    """The reader's notices: a rotated input, skipped corrupt packets."""
    if reader.rotation:
        notify(f"input rotated {reader.rotation} degrees: frames turned upright")
    stats.corrupt_packets = reader.corrupt
    if reader.corrupt:
        notify(f"{src}: skipped {reader.corrupt} corrupt packet(s)")


def iter_frames(
    src: str | os.PathLike,
    transform: RgbaTransform | None = None,
    options: VideoOptions | None = None,
) -> Iterator[tuple[float, np.ndarray]]:
    """Yield ``(t, rgba)`` for each upright frame of ``src`` in ``start``..``end``,
    through ``transform`` when given. Only ``start``/``end``/``notify`` of ``options`` apply."""
    options = options or VideoOptions()
    check_range(options.start, options.end)
    stats = Stats()
    with open_input(src) as container:
        reader = Reader(container, options.start, options.end, {})
        for item in reader.items():
            rgba = item.rgba if transform is None else check_frame(transform(item.rgba, item.t))
            yield item.t, rgba
        if reader.corrupt:
            notify(options, stats, f"{src}: skipped {reader.corrupt} corrupt packet(s)")


def render_sheet(
    dst: str | os.PathLike,
    render_at: Callable[[float], np.ndarray] | PipelinedSource,
    duration: float,
    fps: float,
    options: VideoOptions | None = None,
    *,
    plan: OutputPlan | None = None,
    notes: tuple[str, ...] = (),
) -> Stats:
    """Write ``dst`` from frames ``render_at(i / fps)``, ``i = 0 .. ceil(duration * fps) - 1``
    (a blank sheet's, or a still's: :class:`marblevideo.marbler.SheetSource`),
    telling ``notes`` first; ``duration`` and ``fps`` > 0 (as
    :func:`marblevideo.jobs.options.video_options` checks).

    Constant frame rate (time base 1/fps for integer rates), no audio but
    ``options.soundtrack``, colours untagged (BT.601, limited range). For a
    yuv420p output from a ``planar``
    :class:`~marblevideo.jobs.transforms.PipelinedSource`, the frames are made as
    I420 (:func:`~marblevideo.jobs.route.sheet_route`), one in flight, and swscale
    is skipped. ``plan`` as for :func:`transcode`.
    """
    options = options or VideoOptions()
    began = time.monotonic()
    if plan is None:
        plan = plan_output(dst, options)
        check_output(dst, options.overwrite)
    stats = Stats()
    for note in notes:
        notify(options, stats, note)
    rate = rate_fraction(fps)
    count = int(np.ceil(duration * fps - 1e-9))
    source = sheet_source(render_at)
    render = SheetStage(source, sheet_route(source.planar, source.moves, plan))

    def produce() -> Iterator[VideoItem]:
        items = (VideoItem(None, i, 1, i / fps) for i in range(count))
        return items if sound is None else sound.mixed(items, 1 / rate)

    def setup(writer: Writer, first: VideoItem) -> None:
        height, width = first.shape
        writer.open_video(width, height, 1 / rate, rate, {})
        if audio:
            writer.open_audio({sound.stream.index: (sound.stream, audio[sound.stream.index])})

    with (
        opened(options.soundtrack) as sound,
        video_writer(dst, plan, options, stats) as writer,
        library_logs(options.verbose),
    ):
        audio = {} if sound is None else sound.plan(plan, options, job_notify(options, stats))
        stats.audio = next(iter(audio.values()), "none")
        run_stages(writer, plan, _progress(options), produce, render, setup, count)
    stats.seconds = time.monotonic() - began
    return stats
