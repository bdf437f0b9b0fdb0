"""The live preview's JPEGs: the newest frame shown, encoded in a thread of its
own and handed to every client that asks (``/frame.jpg``, ``/stream.mjpg``).

Frames reach the encoder through a one-slot mailbox: when it is behind, the
older frame is dropped (:attr:`JpegPreview.skipped`), never queued. Each JPEG
gets the next sequence number (1, 2, ...), so a client asks for one newer than
the last it has, and keeps its frame's tag (the serial of the designer's preview
it shows, 0 for none: ``X-Preview-Serial``, so the page knows which of its
inputs a frame shows) and the animation clock's time it was marbled at
(``X-Frame-Time``, so the page can warp it to a gesture's newer state).
"""

from __future__ import annotations

import threading
import time

import cv2
import numpy as np

from marblevideo.live.meters import RateWindow
from marblevideo.live.sources import Latest

Time = float | None  # a frame's clock time, when known


class JpegPreview:
    """JPEGs of the frames shown, ``width`` pixels wide at most (None: as shown),
    at JPEG ``quality`` (1..100); ``mark(tag, "ready")`` is called as each is
    ready (:class:`~marblevideo.live.meters.PreviewTimes`)."""

    def __init__(self, width: int | None = None, quality: int = 80, mark=None):
        self.width = width
        self.quality = quality
        self.mark = mark
        self.shown = Latest()  # frames for the encoder: (RGBA, capture time, tag, clock time)
        self.seq = 0
        self._data: bytes | None = None
        self._tag = 0
        self._time: Time = None
        self._cond = threading.Condition()
        self._closed = False

    @property
    def skipped(self) -> int:
        """Frames shown that the encoder never took (it was behind)."""
        return self.shown.dropped

    def put(self, rgba: np.ndarray, ts: float | None, tag: int = 0, t: Time = None) -> None:
        """Offer a frame shown (RGBA), captured at ``ts`` (``time.monotonic()``;
        None: a captured frame marbled again, not in the latency), with its ``tag``
        and the clock time ``t`` it was marbled at (None: unknown)."""
        self.shown.put((rgba, ts, tag, t))

    def run(self, stop: threading.Event, latency: RateWindow) -> None:
        """Encode until ``stop``; each JPEG's capture-to-ready seconds go to ``latency``."""
        params = [cv2.IMWRITE_JPEG_QUALITY, int(self.quality)]
        while not stop.is_set():
            item = self.shown.get(timeout=0.2)
            if item is None:
                continue
            rgba, ts, tag, t = item
            if self.width and self.width < rgba.shape[1]:
                h = max(1, round(rgba.shape[0] * self.width / rgba.shape[1]))
                rgba = cv2.resize(rgba, (self.width, h), interpolation=cv2.INTER_AREA)
            ok, buf = cv2.imencode(".jpg", cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGR), params)
            if not ok:
                continue
            done = time.monotonic()
            if ts is not None:
                latency.add(done, done - ts)
            if self.mark is not None:
                self.mark(tag, "ready")
            with self._cond:
                self._data, self._tag, self._time = buf.tobytes(), tag, t
                self.seq += 1
                self._cond.notify_all()

    def latest(self, after: int, timeout: float = 1.0) -> tuple[int, bytes | None, int, Time]:
        """Wait for a JPEG newer than sequence ``after``: (seq, bytes, its tag, its
        clock time or None), or (after, None, 0, None) after ``timeout`` seconds or
        once closed."""
        with self._cond:
            self._cond.wait_for(lambda: self.seq > after or self._closed, timeout)
            if self.seq > after and self._data is not None:
                return self.seq, self._data, self._tag, self._time
            return after, None, 0, None

    def close(self) -> None:
        """Wake every client waiting; the encoder thread ends with its ``stop``."""
        self.shown.close()
        with self._cond:
            self._closed = True
            self._cond.notify_all()
