"""What the designer draws over: nothing (a blank sheet), a still image, a video
(any frame, by time) or a live source (its newest frame), as RGBA uint8.

:func:`open_backdrop` tells them apart as the main command and ``marblevideo
live`` do: an image file is a still, another file or URL a video, and
``test``, a camera index or ``/dev/videoN`` a live source.
"""

from __future__ import annotations

import contextlib
import os
import re
import threading
import time
from pathlib import Path

import numpy as np

from marblevideo.errors import MarbleError, MediaError, UsageError
from marblevideo.media.formats import is_image_name

LIVE = re.compile(r"^(test|\d+|/dev/video\d+)$")


class Backdrop:
    """A blank sheet: no image at any time."""

    kind = "blank"
    name = ""
    size: tuple[int, int] | None = None  # (width, height) of the frames
    duration = 0.0  # seconds of video to scrub (0: none)

    def frame(self, t: float) -> np.ndarray | None:
        return None

    def close(self) -> None:
        pass


class Still(Backdrop):
    kind = "image"

    def __init__(self, path: str | os.PathLike):
        from marblevideo.media.images import read_image

        self.name = str(path)
        self.image = read_image(path)[0]
        self.size = (self.image.shape[1], self.image.shape[0])

    def frame(self, t: float) -> np.ndarray:
        return self.image


class Video(Backdrop):
    """A video file or URL: the frame shown at ``t`` (the last one after its end),
    each grabbed from a fresh demuxer (a seek from the nearest key frame)."""

    kind = "video"

    def __init__(self, src: str):
        import av

        self.name = src
        self._lock = threading.Lock()
        with self._opened() as container:
            t0, first = self._grab(container, None)
            self.duration = max(0.0, (container.duration or 0) / av.time_base - t0)
        self.size = (first.shape[1], first.shape[0])
        self._first = (t0, first)
        self._cached = self._first

    def _opened(self):
        from marblevideo.media.decode import open_input

        return contextlib.closing(open_input(self.name))

    @staticmethod
    def _grab(container, t: float | None):
        from marblevideo.media.decode import grab_frame

        return grab_frame(container, t)

    def frame(self, t: float) -> np.ndarray:
        t = min(max(0.0, t), self.duration)
        if t <= self._first[0]:
            return self._first[1]
        with self._lock:
            if self._cached[0] != t:
                # past the last frame: keep the frame shown
                with self._opened() as container, contextlib.suppress(MarbleError):
                    self._cached = (t, self._grab(container, t)[1])
            return self._cached[1]


class LiveFeed(Backdrop):
    """A live source (:func:`marblevideo.live.sources.open_source`, or ``source``
    already made): its newest frame. One thread takes the source's frames, in
    order, and hands each to ``seen`` (a callable of a
    :class:`~marblevideo.live.sources.Captured`, set by its user: the designer's
    motion, :mod:`marblevideo.design.motion`) before it is shown; frames that come
    faster than ``seen`` takes them are dropped, as in a live session.
    ``started``: the monotonic time the source was started at."""

    kind = "live"

    def __init__(self, spec: str, size: tuple[int, int] | None = None, source=None):
        from marblevideo.live.sources import open_source

        self.name = spec
        self.source = source or open_source(spec, size, None, loop=True)
        self.size = self.source.size
        self.seen = None
        self.started = time.monotonic()
        self.source.start()
        first = self.source.frames.get(timeout=10.0)
        if first is None:
            self.source.stop()
            raise MediaError(f"{spec}: no frame from the live source") from self.source.error
        self._last = first.rgba
        self.size = (first.rgba.shape[1], first.rgba.shape[0])
        self._stop = threading.Event()
        self._taker = threading.Thread(target=self._take, name="marblevideo-feed", daemon=True)
        self._taker.start()

    def _take(self) -> None:
        while not self._stop.is_set():
            cap = self.source.frames.get(timeout=0.1)
            if cap is None:
                continue
            seen = self.seen
            if seen is not None:
                seen(cap)
            self._last = cap.rgba

    def frame(self, t: float) -> np.ndarray:
        return self._last

    def close(self) -> None:
        self._stop.set()
        self._taker.join(5.0)
        self.source.stop()


def check_spec(spec: str) -> None:
    """UsageError when ``spec`` names no source, file nor URL."""
    if not LIVE.match(spec) and "://" not in spec and not Path(spec).is_file():
        raise UsageError(
            f"{spec}: no such file (an input is an image, a video, a URL, 'test', "
            "a camera index or /dev/videoN)"
        )


def open_backdrop(spec: str | None, size: tuple[int, int] | None = None) -> Backdrop:
    """The backdrop ``spec`` names (None: a blank sheet)."""
    if spec is None:
        return Backdrop()
    check_spec(spec)
    if LIVE.match(spec):
        return LiveFeed(spec, size)
    if is_image_name(spec):
        return Still(spec)
    return Video(spec)
