"""The three stages of a video render, in threads joined by bounded queues:
decode (a producer of items) -> transform (the calling thread, in place) ->
encode (a writer of :mod:`marblevideo.media.sinks`).

Each queue holds at most ``QUEUE_FRAMES`` items, so memory stays flat. The
first error in any stage stops the others and is re-raised in the caller;
KeyboardInterrupt propagates after the threads are stopped. The transform may
return a function that finishes its item: it is called once the next frame has
been started, so one frame is in flight (a device renders while the host
prepares the next one).
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable, Iterator

import av

from marblevideo.errors import MediaError
from marblevideo.media.encode import Encoder, OutputPlan
from marblevideo.media.progress import Progress
from marblevideo.media.sinks import SequenceWriter
from marblevideo.media.video import QUEUE_FRAMES, AudioItem, VideoItem

END = object()
"""The item after the last one in a queue."""

Writer = Encoder | SequenceWriter


class Stopped(Exception):
    """Raised inside a stage when another stage stopped the pipeline."""


class Stages:
    """Stage threads joined by bounded queues; the first error stops them all."""

    POLL = 0.1

    def __init__(self):
        self.stop = threading.Event()
        self.error: BaseException | None = None
        self.threads: list[threading.Thread] = []

    def put(self, q: queue.Queue, item) -> None:
        while True:
            if self.stop.is_set():
                raise Stopped
            try:
                q.put(item, timeout=self.POLL)
                return
            except queue.Full:
                pass

    def get(self, q: queue.Queue):
        while True:
            if self.stop.is_set() and q.empty():
                raise Stopped
            try:
                return q.get(timeout=self.POLL)
            except queue.Empty:
                pass

    def start(self, name: str, target: Callable[[], None]) -> None:
        def run():
            try:
                target()
            except Stopped:
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

    def wait(self) -> None:
        """Join every stage in short steps, which keep Ctrl-C responsive."""
        for thread in self.threads:
            while thread.is_alive():
                thread.join(self.POLL)


def _decode(pipe: Stages, produce: Callable[[], Iterator], decoded: queue.Queue) -> None:
    for item in produce():
        pipe.put(decoded, item)
    pipe.put(decoded, END)


def _encode(
    pipe: Stages,
    marbled: queue.Queue,
    writer: Writer,
    plan: OutputPlan,
    setup: Callable[[Writer, VideoItem], None],
) -> None:
    """Write items until END; audio before the first frame is held until the
    first frame has opened the streams (``setup``)."""
    try:
        while (item := pipe.get(marbled)) is not END:
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


def _transform(
    pipe: Stages,
    decoded: queue.Queue,
    marbled: queue.Queue,
    transform: Callable[[VideoItem], Callable[[], None] | None],
    bar: Progress,
) -> None:
    """RgbaTransform each frame in order, keeping one frame in flight: a frame's
    finish is called after the next frame has been started."""
    flight: list = []  # (item, finish or None), in order; one frame among them

    def land() -> None:
        for item, finish in flight:
            if finish is not None:
                finish()
            if isinstance(item, VideoItem):
                bar.update()
            pipe.put(marbled, item)
        flight.clear()

    while (item := pipe.get(decoded)) is not END:
        finish = None
        if isinstance(item, VideoItem):
            finish = transform(item)  # started: now the frame before can land
            land()
        flight.append((item, finish))
    land()
    pipe.put(marbled, END)


def run_stages(
    writer: Writer,
    plan: OutputPlan,
    progress: str,
    produce: Callable[[], Iterator[VideoItem | AudioItem]],
    transform: Callable[[VideoItem], Callable[[], None] | None],
    setup: Callable[[Writer, VideoItem], None],
    total: int | None,
) -> None:
    """Decode (``produce``) -> transform (this thread, in place) -> encode
    (``writer``), with a ``progress`` bar (a :class:`Progress` mode) of ``total``
    frames (None: unknown)."""
    pipe = Stages()
    decoded: queue.Queue = queue.Queue(QUEUE_FRAMES)
    marbled: queue.Queue = queue.Queue(QUEUE_FRAMES)
    try:
        with Progress(total, mode=progress) as bar:
            pipe.start("decode", lambda: _decode(pipe, produce, decoded))
            pipe.start("encode", lambda: _encode(pipe, marbled, writer, plan, setup))
            _transform(pipe, decoded, marbled, transform, bar)
            pipe.wait()
    except Stopped:
        pass  # a stage failed: its error is raised below
    finally:
        pipe.stop.set()
        pipe.join()
    if pipe.error is not None:
        raise pipe.error
