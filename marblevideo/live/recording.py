"""Recording a live session: frames at their wall-clock times, encoded as in file mode.

Timing: variable frame rate. Each frame's pts is its capture time minus the
first recorded frame's, in milliseconds (time base 1/1000), so the file plays
back at the pace it was shown, dropped frames included as gaps. Encoder
settings are the file mode's, checked by :func:`marblevideo.media.encode.plan_output`
(--codec, --crf, --preset, --pix-fmt, --encoder-opt), and frames are written
by its writers (:func:`marblevideo.media.sinks.video_writer`: a file, a GIF,
an image sequence, standard output).

Encoding runs in its own thread behind a small bounded queue; a frame that
finds the queue full is dropped and counted (``dropped``), so a slow encoder
never holds back the live picture. A file goes through
:func:`marblevideo.media.output.atomic_output`: :meth:`Recorder.close` with
``ok=True`` finalizes and renames it; ``ok=False`` removes it.
"""

from __future__ import annotations

import contextlib
import os
import queue
import threading
from fractions import Fraction

import numpy as np

from marblevideo.media.encode import plan_output
from marblevideo.media.sinks import video_writer
from marblevideo.media.video import Stats, VideoItem, VideoOptions

TIME_BASE = Fraction(1, 1000)
QUEUE = 8


class Recorder:
    """Encode RGBA frames given with their capture times into ``dst``."""

    def __init__(self, dst: str | os.PathLike, options: VideoOptions):
        self.dst = dst
        self.options = options
        self.plan = plan_output(dst, options)  # every setting checked before anything opens
        self.stats = Stats()
        self.dropped = 0
        self._queue: queue.Queue = queue.Queue(QUEUE)
        self._thread: threading.Thread | None = None
        self._stack = contextlib.ExitStack()
        self._error: BaseException | None = None
        self._origin: float | None = None
        self._last_pts = -1
        self._started = False

    def start(self, width: int, height: int, fps: float) -> None:
        """Open the (temporary) output for frames of ``width`` x ``height``."""
        self._started = True
        self._writer = self._stack.enter_context(
            video_writer(self.dst, self.plan, self.options, self.stats)
        )
        rate = Fraction(fps).limit_denominator(1001) if fps > 0 else None
        self._writer.open_video(width, height, TIME_BASE, rate, {})
        self._thread = threading.Thread(target=self._run, name="marblevideo-record", daemon=True)
        self._thread.start()

    def add(self, rgba: np.ndarray, ts: float) -> None:
        """Queue a frame captured at ``ts`` (monotonic seconds); drop it when the queue is full."""
        if self._error is not None:
            raise self._error
        if self._origin is None:
            self._origin = ts
        pts = round((ts - self._origin) / TIME_BASE)
        if pts <= self._last_pts:  # same millisecond as the previous frame
            self.dropped += 1
            return
        try:
            self._queue.put_nowait(VideoItem(rgba, pts, 0, ts - self._origin))
            self._last_pts = pts
        except queue.Full:
            self.dropped += 1

    def _run(self) -> None:
        try:
            while (item := self._queue.get()) is not None:
                self._writer.video(item)
        except BaseException as exc:  # noqa: BLE001 - re-raised by add/close
            self._error = exc
            while self._queue.get() is not None:  # drain so close() does not block
                pass

    def close(self, ok: bool = True) -> None:
        """Finish: encode what is queued, flush, and keep the file (``ok``) or remove it."""
        if not self._started:
            return
        if self._thread is not None:
            self._queue.put(None)
            self._thread.join()
            self._thread = None
        error = self._error
        try:
            if ok and error is None:
                self._writer.flush()
        except BaseException as exc:
            error = exc
        if ok and error is None:
            self._stack.close()
            return
        self._stack.__exit__(type(error or KeyboardInterrupt), error, None)
        if error is not None:
            raise error

    @property
    def frames(self) -> int:
        return self.stats.frames
