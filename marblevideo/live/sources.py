"""Live sources: a camera, a media file or URL played in real time, or a test pattern.

Each source runs one capture thread that publishes upright RGBA uint8 frames
into a :class:`Latest` mailbox, a one-slot box that keeps only the newest
frame: when the consumer is behind, older frames are replaced (and counted as
dropped) instead of queued, so latency stays bounded. Every frame carries its
capture time on :func:`time.monotonic`'s clock.

:func:`open_source` turns the command line's SOURCE into a source:
``test`` (the built-in pattern), an integer or ``/dev/videoN`` (a camera through
OpenCV), anything else a file or URL that PyAV opens.
"""

from __future__ import annotations

import re
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from marblevideo.errors import MediaError
from marblevideo.limits import DEFAULT_FPS


@dataclass
class Captured:
    """One captured frame: RGBA (H, W, 4) uint8, capture time (monotonic s), sequence
    number, for a file its time in the file (s; None for live devices), and for a
    decoded YUV frame its luma plane as decoded (H, W) uint8, which the motion
    sees as a file render's does (None: the motion takes the RGBA's luma)."""

    rgba: np.ndarray
    ts: float
    seq: int
    media_t: float | None = None
    luma: np.ndarray | None = None


class Latest:
    """A one-slot mailbox: ``put`` replaces what is there, ``get`` waits for something newer."""

    def __init__(self):
        self._cond = threading.Condition()
        self._item = None
        self._seq = 0  # of the last put
        self._taken = 0  # seq of the last get
        self.dropped = 0  # items replaced before anyone took them
        self.closed = False
        self._woken = False

    def put(self, item) -> None:
        with self._cond:
            if self._seq > self._taken:
                self.dropped += 1
            self._item = item
            self._seq += 1
            self._cond.notify_all()

    def get(self, timeout: float | None = None):
        """The newest item not yet taken, or None on timeout, when closed and empty,
        or when woken (:meth:`wake`) with nothing new."""
        with self._cond:
            if not self._cond.wait_for(
                lambda: self._seq > self._taken or self.closed or self._woken, timeout=timeout
            ):
                return None
            self._woken = False
            if self._seq <= self._taken:
                return None
            self._taken = self._seq
            return self._item

    def wake(self) -> None:
        """Make the ``get`` waiting now (or the next) return at once, with None
        when nothing new came (the live loop: a new recipe to show)."""
        with self._cond:
            self._woken = True
            self._cond.notify_all()

    def close(self) -> None:
        with self._cond:
            self.closed = True
            self._cond.notify_all()

    @property
    def waiting(self) -> bool:
        """Whether the last item put has not been taken yet."""
        with self._cond:
            return self._seq > self._taken


class Source:
    """Base of the live sources: a capture thread feeding ``frames`` until ``stop``."""

    name = "source"

    def __init__(self):
        self.frames = Latest()
        self.size: tuple[int, int] = (0, 0)  # (width, height) of the frames
        self.fps: float = DEFAULT_FPS  # nominal rate
        self.error: BaseException | None = None
        self.ended = False  # the source has no more frames (end of a file without --loop)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._seq = 0

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="marblevideo-capture", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            self.capture()
        except BaseException as exc:  # noqa: BLE001 - reported by the render loop
            self.error = exc
        finally:
            self.ended = True
            self.frames.close()

    def publish(
        self,
        rgba: np.ndarray,
        ts: float | None = None,
        media_t: float | None = None,
        luma: np.ndarray | None = None,
    ) -> None:
        self._seq += 1
        now = time.monotonic() if ts is None else ts
        self.frames.put(Captured(rgba, now, self._seq, media_t, luma))

    def capture(self) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(5.0)
        self.close()

    def close(self) -> None:
        pass


class TestPattern(Source):
    """A moving colour pattern with a clock, so that every frame differs visibly."""

    __test__ = False  # not a pytest class
    name = "test pattern"

    def __init__(self, size: tuple[int, int] = (1280, 720), fps: float = DEFAULT_FPS):
        super().__init__()
        self.size, self.fps = size, fps
        w, h = size
        y, x = np.mgrid[0:h, 0 : 2 * w].astype(np.float32)
        base = np.empty((h, 2 * w, 4), dtype=np.uint8)
        base[..., 0] = (127.5 + 127.5 * np.sin(x * (2 * np.pi / w))).astype(np.uint8)
        base[..., 1] = (255 * y / max(h - 1, 1)).astype(np.uint8)
        base[..., 2] = (127.5 + 127.5 * np.cos((x + y) * (4 * np.pi / w))).astype(np.uint8)
        base[..., 3] = 255
        step = max(8, min(w, h) // 12)
        base[:, ::step] = (255, 255, 255, 255)  # a grid shows every deformation
        base[::step, :] = (255, 255, 255, 255)
        self._base = np.concatenate([base, base[:, :w]], axis=1)  # wraps without a seam
        self._start = time.monotonic()

    def frame(self, t: float, n: int) -> np.ndarray:
        w, h = self.size
        offset = int(t * w / 8) % (2 * w)  # scrolls one frame width every 8 s
        rgba = np.ascontiguousarray(self._base[:, offset : offset + w])
        scale = max(0.4, h / 360)
        text = f"{t:7.2f} s  #{n}"
        org = (int(12 * scale), int(40 * scale))
        for color, thickness in (((0, 0, 0, 255), 6), ((255, 255, 255, 255), 2)):
            font = cv2.FONT_HERSHEY_SIMPLEX
            cv2.putText(rgba, text, org, font, scale, color, thickness, cv2.LINE_AA)
        cx = int(w / 2 + w / 3 * np.cos(t * 2.0))
        cy = int(h / 2 + h / 3 * np.sin(t * 2.0))
        cv2.circle(rgba, (cx, cy), max(4, h // 16), (255, 230, 0, 255), -1, cv2.LINE_AA)
        return rgba

    def capture(self) -> None:
        period = 1.0 / self.fps
        n = 0
        next_at = time.monotonic()
        while not self._stop.is_set():
            now = time.monotonic()
            if now < next_at:
                self._stop.wait(next_at - now)
                continue
            ts = time.monotonic()
            self.publish(self.frame(ts - self._start, n), ts)
            n += 1
            next_at += period
            if next_at < ts - period:  # far behind: do not try to catch up
                next_at = ts + period


class CameraSource(Source):
    """A camera through OpenCV's VideoCapture (an index, or a device path such as /dev/video0)."""

    def __init__(self, device: int | str, size: tuple[int, int] | None, fps: float | None):
        super().__init__()
        self.name = f"camera {device}"
        cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_ERROR)  # our one line says it
        cap = cv2.VideoCapture(device)
        if not cap.isOpened():
            raise MediaError(f"camera {device}: cannot open it (is it connected and free?)")
        if size is not None:
            cap.set(cv2.CAP_PROP_FRAME_WIDTH, size[0])
            cap.set(cv2.CAP_PROP_FRAME_HEIGHT, size[1])
        if fps is not None:
            cap.set(cv2.CAP_PROP_FPS, fps)
        ok, bgr = cap.read()
        if not ok or bgr is None:
            cap.release()
            raise MediaError(f"camera {device}: opened but gave no frame")
        self._cap = cap
        self._first = bgr
        self.size = (bgr.shape[1], bgr.shape[0])
        self.fps = cap.get(cv2.CAP_PROP_FPS) or fps or DEFAULT_FPS

    @staticmethod
    def _rgba(bgr: np.ndarray) -> np.ndarray:
        code = cv2.COLOR_GRAY2RGBA if bgr.ndim == 2 else cv2.COLOR_BGR2RGBA
        return cv2.cvtColor(bgr, code)

    def capture(self) -> None:
        self.publish(self._rgba(self._first))
        self._first = None
        while not self._stop.is_set():
            ok, bgr = self._cap.read()
            ts = time.monotonic()
            if not ok:
                raise MediaError(f"{self.name}: stopped giving frames")
            self.publish(self._rgba(bgr), ts)

    def close(self) -> None:
        self._cap.release()


class MediaSource(Source):
    """A file or URL decoded by PyAV and released at real-time pace (its own pts).

    With ``loop`` the input is opened again at its end (which also loops a still
    image, shown at the stream's nominal rate) and its clock continues.
    """

    def __init__(self, url: str, loop: bool = False):
        super().__init__()
        self.name, self.url, self.loop = url, url, loop
        if "://" not in url and not Path(url).is_file():
            raise MediaError(
                f"{url}: no such file (a source is a camera index, /dev/videoN, a file, "
                "a URL, or test)"
            )
        self._container = self._open()
        stream = self._container.streams.video[0]
        self.size = (stream.codec_context.width, stream.codec_context.height)
        rate = stream.average_rate or stream.guessed_rate
        self.fps = float(rate) if rate else DEFAULT_FPS

    def _open(self):
        import av

        try:
            container = av.open(self.url)
        except av.error.FFmpegError as exc:
            raise MediaError(f"{self.url}: cannot open ({exc.strerror})") from None
        if not container.streams.video:
            container.close()
            raise MediaError(f"{self.url}: no video stream")
        container.streams.video[0].thread_type = "AUTO"
        return container

    def capture(self) -> None:
        from marblevideo.media.decode import frame_luma, upright

        origin = time.monotonic()  # wall-clock time of t = 0 of the current pass
        while not self._stop.is_set():
            stream = self._container.streams.video[0]
            clock = stream.start_time or 0
            last = 0.0
            for frame in self._container.decode(stream):
                if frame.pts is None:
                    continue
                t = float((frame.pts - clock) * stream.time_base)
                last = max(last, t)
                delay = origin + t - time.monotonic()
                if delay > 0 and self._stop.wait(delay):
                    return
                if self._stop.is_set():
                    return
                self.publish(upright(frame), media_t=t, luma=_copy(frame_luma(frame)))
            if not self.loop:
                return
            self._container.close()
            self._container = self._open()
            origin += last + 1.0 / self.fps
            if origin < time.monotonic() - 1.0:  # far behind (slow decoding): do not catch up
                origin = time.monotonic()

    def close(self) -> None:
        self._container.close()


def _copy(plane: np.ndarray | None) -> np.ndarray | None:
    """A plane of its own (a decoded frame's buffer is the decoder's to reuse)."""
    return None if plane is None else plane.copy()


_DEVICE = re.compile(r"^/dev/video\d+$")


def open_source(
    spec: str, size: tuple[int, int] | None = None, fps: float | None = None, loop: bool = False
) -> Source:
    """The source named by ``spec``: "test", a camera index or /dev/videoN, or a file/URL."""
    if spec == "test":
        return TestPattern(size or (1280, 720), fps or DEFAULT_FPS)
    if spec.isdigit():
        return CameraSource(int(spec), size, fps)
    if _DEVICE.match(spec):
        return CameraSource(spec, size, fps)
    return MediaSource(spec, loop)
