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
- A transform may also offer ``transform.i420(planes, t, src, dst) -> planes``
  (:class:`PlanarTransform`):
  the frame as I420 planes ``(y, u, v)`` (:mod:`marblevideo.media.yuv`; views of the
  decoded frame's buffers, rows possibly padded: read them, do not keep them)
  with colours in the :class:`~marblevideo.media.yuv.YuvMatrix` ``src``, the result as
  I420 in ``dst``, packed or as planes, in arrays of its own (a packed result
  is encoded without a copy). With ``transform.i420_start(planes, t, src, dst)
  -> finish`` as well (:class:`PlanarStart`), the pipeline keeps one frame in
  flight: it starts frame n + 1 before calling frame n's ``finish()``, which returns what ``i420``
  would have, so a device renders while the host prepares the next frame
  (:meth:`marblevideo.marbler.VideoTransform.i420_start`); the planes stay the
  pipeline's until ``finish`` returns. ``transform.rgba_start(rgba, t) ->
  finish`` (:class:`RgbaStart`) does the same for frames that go the RGBA way.
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

import os
import queue
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Protocol, runtime_checkable

import av
import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.media.decode import Reader, estimate_frames, open_input
from marblevideo.media.encode import COLOR_FIELDS, Encoder, OutputPlan, audio_plan, plan_output
from marblevideo.media.encoders import library_logs
from marblevideo.media.formats import is_local, is_sequence
from marblevideo.media.output import check_output
from marblevideo.media.progress import Progress, progress_mode
from marblevideo.media.retime import rate_fraction, retimed
from marblevideo.media.sinks import SequenceWriter, video_writer
from marblevideo.media.soundtrack import opened
from marblevideo.media.video import (
    QUEUE_FRAMES,
    AudioItem,
    Stats,
    VideoItem,
    VideoOptions,
    check_range,
    notifier,
    say,
)
from marblevideo.media.yuv import YuvMatrix, split_i420
from marblevideo.recipe.frame import stretch_note

Transform = Callable[[np.ndarray, float], np.ndarray]
"""``transform(rgba, t) -> rgba``; it may also be a :class:`PlanarTransform`, a
:class:`PlanarStart` and a :class:`RgbaStart` (see the module)."""


@runtime_checkable
class PlanarTransform(Protocol):
    """A transform that takes and gives 8-bit 4:2:0 frames (see the module)."""

    def i420(self, planes, t: float, src: YuvMatrix, dst: YuvMatrix): ...


@runtime_checkable
class PlanarStart(Protocol):
    """:class:`PlanarTransform` with one frame in flight: returns a function that
    finishes the frame."""

    def i420_start(self, planes, t: float, src: YuvMatrix, dst: YuvMatrix) -> Callable: ...


@runtime_checkable
class RgbaStart(Protocol):
    """A transform with one RGBA frame in flight: returns a function that finishes it."""

    def rgba_start(self, rgba: np.ndarray, t: float) -> Callable[[], np.ndarray]: ...


@runtime_checkable
class PlanarSource(Protocol):
    """Frames of a blank sheet (:func:`render_sheet`) that can come as I420."""

    def i420(self, t: float, matrix: YuvMatrix) -> np.ndarray | None: ...


@runtime_checkable
class PlanarSourceStart(Protocol):
    """:class:`PlanarSource` with one frame in flight."""

    def i420_start(self, t: float, matrix: YuvMatrix) -> Callable | None: ...


_END = object()


class _Stopped(Exception):
    """Raised inside a stage when another stage stopped the pipeline."""


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
    writer: Encoder | SequenceWriter,
    plan: OutputPlan,
    options: VideoOptions,
    produce: Callable[[], Iterator[VideoItem | AudioItem]],
    transform: Callable[[VideoItem], Callable[[], None] | None],
    setup: Callable[[Encoder | SequenceWriter, VideoItem], None],
    total: int | None,
) -> None:
    """Decode (``produce``) -> transform (this thread, in place) -> encode (``writer``,
    :mod:`marblevideo.media.sinks`), with bounded queues. ``transform`` may return a
    function that finishes the item: it is called once the next frame has been
    started (one frame in flight)."""
    pipe = _Pipeline()
    decoded: queue.Queue = queue.Queue(QUEUE_FRAMES)
    marbled: queue.Queue = queue.Queue(QUEUE_FRAMES)

    def decode():
        for item in produce():
            pipe.put(decoded, item)
        pipe.put(decoded, _END)

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
            what = plan.codec or plan.format
            raise MediaError(f"{what} encoding failed: {exc.strerror}") from None

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
    except _Stopped:
        pass  # a stage failed: its error is raised below
    finally:
        pipe.stop.set()
        pipe.join()
    if pipe.error is not None:
        raise pipe.error


def transcode(
    src: str | os.PathLike,
    dst: str | os.PathLike,
    transform: Transform,
    options: VideoOptions | None = None,
    *,
    plan: OutputPlan | None = None,
    stream=None,
    pts_origin: int | None = None,
) -> Stats:
    """Write ``dst``: every frame of ``src`` (in ``start``..``end``) through ``transform``.

    ``src`` is a file, an image sequence, ``-`` (standard input; ``stream`` is
    :func:`~marblevideo.media.decode.stdin_source`'s when it was read already)
    or a URL; ``dst`` a file, an image sequence or ``-`` (standard output, in
    ``options.format``). With ``options.fps`` the frame rate is converted
    (:mod:`marblevideo.media.retime`); for an image sequence it is the rate
    the images are read at instead.

    Raises UsageError (bad options, output = input), OutputExistsError,
    MediaError (unreadable input, encoder failure); exceptions from
    ``transform`` and KeyboardInterrupt propagate, leaving no output file.
    ``plan`` is :func:`plan_output`'s for ``dst`` and ``options``, where the
    caller has checked them already. ``pts_origin``: see
    :class:`~marblevideo.media.decode.Reader` (segments of a split render).
    """
    options = options or VideoOptions()
    began = time.monotonic()
    plan = plan or plan_output(dst, options)
    inputs = [src] if is_local(src) else []
    if not (plan.stream or plan.sequence):
        check_output(dst, options.overwrite, inputs)
    stats = Stats()
    sequence_in = is_sequence(src)
    with open_input(src, options.fps, stream) as container, opened(options.soundtrack) as sound:
        say = notifier(options, stats)
        name = "standard output" if plan.stream else f"{Path(dst).suffix} files"
        own = audio_plan(container, plan, options, name, say) if sound is None else {}
        audio = own or (sound.plan(plan, options, say) if sound else {})
        encoders = set(audio.values()) - {"copy"}
        stats.audio = encoders.pop() if encoders else "copy" if audio else "none"
        vin = container.streams.video[0]
        colors = {k: getattr(vin.codec_context, k) for k in COLOR_FIELDS}
        planar = transform.i420 if isinstance(transform, PlanarTransform) else None
        out_matrix = YuvMatrix.of(colors["colorspace"], colors["color_range"])
        if plan.pix_fmt != "yuv420p" or (options.size and any(v % 2 for v in options.size)):
            out_matrix = None
        reader = Reader(
            container,
            options.start,
            options.end,
            own,
            planar is not None and out_matrix is not None,
            pts_origin,
        )
        convert = options.fps is not None and not sequence_in
        time_base, rate = vin.time_base, vin.average_rate or vin.guessed_rate
        if convert:
            rate = rate_fraction(options.fps)
            time_base = 1 / rate

        def produce() -> Iterator[VideoItem | AudioItem]:
            items = reader.items()
            items = retimed(items, vin.time_base, options.fps) if convert else items
            return items if sound is None else sound.mixed(items, time_base)

        start = None
        if planar is not None and isinstance(transform, PlanarStart):
            start = transform.i420_start
        rgba_start = transform.rgba_start if isinstance(transform, RgbaStart) else None

        first = [True]

        def marble(item: VideoItem) -> Callable[[], None] | None:
            if first[0] and options.size is not None and options.fit is None:
                note = stretch_note(item.shape[::-1], tuple(options.size))
                if note:
                    say(note)
            first[0] = False
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

        def setup(writer: Encoder | SequenceWriter, first: VideoItem) -> None:
            height, width = first.shape
            writer.open_video(width, height, time_base, rate, colors)
            streams = container.streams if sound is None else {sound.stream.index: sound.stream}
            writer.open_audio({i: (streams[i], how) for i, how in audio.items()})

        total = estimate_frames(reader, options.fps if convert else None)
        with (
            video_writer(dst, plan, options, stats, inputs) as writer,
            library_logs(options.verbose),
        ):
            _run(writer, plan, options, produce, marble, setup, total)
        if reader.rotation:
            say(f"input rotated {reader.rotation} degrees: frames turned upright")
        stats.corrupt_packets = reader.corrupt
        if reader.corrupt:
            say(f"{src}: skipped {reader.corrupt} corrupt packet(s)")
    stats.seconds = time.monotonic() - began
    return stats


def iter_frames(
    src: str | os.PathLike, transform: Transform | None = None, options: VideoOptions | None = None
) -> Iterator[tuple[float, np.ndarray]]:
    """Yield ``(t, rgba)`` for each upright frame of ``src`` in ``start``..``end``,
    through ``transform`` when given. Only ``start``/``end``/``notify`` of ``options`` apply."""
    options = options or VideoOptions()
    check_range(options.start, options.end)
    stats = Stats()
    with open_input(src) as container:
        reader = Reader(container, options.start, options.end, {})
        for item in reader.items():
            rgba = item.rgba if transform is None else _check_frame(transform(item.rgba, item.t))
            yield item.t, rgba
        if reader.corrupt:
            say(options, stats, f"{src}: skipped {reader.corrupt} corrupt packet(s)")


def render_sheet(
    dst: str | os.PathLike,
    render_at: Callable[[float], np.ndarray],
    duration: float,
    fps: float,
    options: VideoOptions | None = None,
    *,
    plan: OutputPlan | None = None,
    notes: tuple[str, ...] = (),
) -> Stats:
    """Write ``dst`` from frames ``render_at(i / fps)``, ``i = 0 .. ceil(duration * fps) - 1``
    (a blank sheet's, or a still's: :class:`marblevideo.marbler.SheetFrames`),
    telling ``notes`` first.

    Constant frame rate (time base 1/fps for integer rates), no audio but
    ``options.soundtrack``, colours untagged (BT.601, limited range). For a
    yuv420p output, ``render_at.i420(t, matrix)``, where present, gives the frame
    as I420 in ``matrix`` (None where it cannot, e.g. odd sizes) and swscale is
    skipped; ``render_at.i420_start(t, matrix)``, where present, is used instead:
    it returns a function giving that frame (or None where it cannot), called once
    the next frame is started. ``plan`` as for :func:`transcode`.
    """
    options = options or VideoOptions()
    if duration <= 0 or fps <= 0:
        raise UsageError(f"duration and fps must be positive, got {duration} s at {fps} fps")
    began = time.monotonic()
    plan = plan or plan_output(dst, options)
    stats = Stats()
    for note in notes:
        say(options, stats, note)
    rate = rate_fraction(fps)
    count = int(np.ceil(duration * fps - 1e-9))
    planar = None
    if plan.pix_fmt == "yuv420p" and isinstance(render_at, PlanarSource):
        planar = render_at.i420
    start = None
    if planar is not None and isinstance(render_at, PlanarSourceStart):
        start = render_at.i420_start
    matrix = YuvMatrix.of(None, None)

    def produce() -> Iterator[VideoItem]:
        items = (VideoItem(None, i, 1, i / fps) for i in range(count))
        return items if sound is None else sound.mixed(items, 1 / rate)

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
        if audio:
            writer.open_audio({sound.stream.index: (sound.stream, audio[sound.stream.index])})

    with (
        opened(options.soundtrack) as sound,
        video_writer(dst, plan, options, stats) as writer,
        library_logs(options.verbose),
    ):
        audio = {} if sound is None else sound.plan(plan, options, notifier(options, stats))
        stats.audio = next(iter(audio.values()), "none")
        _run(writer, plan, options, produce, render, setup, count)
    stats.seconds = time.monotonic() - began
    return stats
