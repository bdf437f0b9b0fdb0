"""A live session's meters: frame rate, render time and latency over the last
few seconds, read by ``/stats`` while the render and JPEG threads add to them.

Times are ``time.monotonic()`` seconds; the rounded figures of
:meth:`Meters.figures` are frames per second and milliseconds.
"""

from __future__ import annotations

import contextlib
import statistics
import threading
import time
from collections import deque


class RateWindow:
    """Rates and latencies over the last few seconds. Threads add (the render, the
    JPEG encoder) while others read (``/stats``): every access holds its lock."""

    def __init__(self, span: float = 2.0, keep: int = 120):
        self.span = span
        self.times: deque[float] = deque()
        self.values: deque[float] = deque(maxlen=keep)
        self._lock = threading.Lock()

    def add(self, now: float, value: float | None = None) -> None:
        with self._lock:
            self.times.append(now)
            while self.times and self.times[0] < now - self.span:
                self.times.popleft()
            if value is not None:
                self.values.append(value)

    def rate(self, now: float) -> float:
        with self._lock:
            recent = [t for t in self.times if t >= now - self.span]
        if len(recent) < 2:
            return 0.0
        return (len(recent) - 1) / max(recent[-1] - recent[0], 1e-9)

    def clear(self) -> None:
        """Forget the values kept (a benchmark's warm-up)."""
        with self._lock:
            self.values.clear()

    def _values(self) -> list[float]:
        with self._lock:
            return list(self.values)

    def median(self) -> float | None:
        values = self._values()
        return statistics.median(values) if values else None

    def quantile(self, q: float) -> float | None:
        ordered = sorted(self._values())
        if not ordered:
            return None
        return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def _ms(seconds: float | None, digits: int) -> float | None:
    return None if seconds is None else round(seconds * 1000, digits)


class Meters:
    """The session's three windows: :attr:`rendered` (one mark per frame shown),
    :attr:`render` (seconds each render took) and :attr:`latency` (seconds from
    capture to the JPEG ready)."""

    def __init__(self):
        self.rendered = RateWindow()
        self.render = RateWindow()
        self.latency = RateWindow()

    def frame(self, now: float, render_s: float) -> None:
        """A frame rendered in ``render_s`` seconds, shown at ``now``."""
        self.render.add(now, render_s)
        self.rendered.add(now)

    def clear(self) -> None:
        """Start the medians afresh (after a benchmark's warm-up)."""
        self.render.clear()
        self.latency.clear()

    def figures(self, now: float) -> dict:
        """``/stats``' part: fps, latency median and p95, render median (ms)."""
        return {
            "fps": round(self.rendered.rate(now), 2),
            "latency_ms": _ms(self.latency.median(), 1),
            "latency_p95_ms": _ms(self.latency.quantile(0.95), 1),
            "render_ms": _ms(self.render.median(), 2),
        }


class PreviewTimes:
    """When each of the designer's last previews (by serial) went through the
    session, for ``/stats`` (``preview_times``: serial -> {step: wall-clock ms},
    ``time.time()``'s clock, so a page's ``performance.timeOrigin + now()``
    compares): ``received`` (PUT taken), ``start`` and ``rendered`` (its first
    render), ``ready`` (its first JPEG). Each step is kept the first time only."""

    def __init__(self, keep: int = 256):
        self.keep = keep
        self._times: dict[int, dict[str, float]] = {}
        self._lock = threading.Lock()

    def mark(self, serial: int, step: str, wall: float | None = None) -> None:
        if not serial:
            return
        with self._lock:
            times = self._times.setdefault(serial, {})
            times.setdefault(step, round(1000 * (time.time() if wall is None else wall), 2))
            while len(self._times) > self.keep:
                del self._times[next(iter(self._times))]

    def rendered(self, serial: int, seconds: float) -> None:
        """``serial``'s render ended now and took ``seconds``: its start and end."""
        now = time.time()
        self.mark(serial, "start", now - seconds)
        self.mark(serial, "rendered", now)

    @contextlib.contextmanager
    def rendering(self, serial: int):
        """Marks ``serial``'s render: the ``with`` block's start and end."""
        start = time.monotonic()
        yield
        self.rendered(serial, time.monotonic() - start)

    def figures(self) -> dict[str, dict[str, float]]:
        with self._lock:
            return {str(k): dict(v) for k, v in self._times.items()}
