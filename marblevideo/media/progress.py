"""Progress reports for long jobs, on stderr.

Three modes: ``"bar"`` (a tqdm bar: count, rate, ETA), ``"json"`` (one JSON
line per second, ``{"frame", "total", "fps", "time", "eta"}``, for other
programs; ``time`` and ``eta`` in seconds, ``total``/``eta`` null when
unknown; work counted in other units names them: ``{"segment", "total",
"per_second", ...}`` for ``--cluster``, ``"item"`` for batches, ``"band"`` for
big stills) and ``"off"``. :func:`progress_mode` turns the CLI's flags into one.
"""

from __future__ import annotations

import json
import sys
import time
from typing import TextIO

MODES = ("auto", "bar", "json", "off")


def progress_mode(progress: str = "auto", quiet: bool = False, stream: TextIO | None = None) -> str:
    """``quiet`` wins; ``"auto"`` is a bar when ``stream`` (stderr) is a terminal, else off."""
    if progress not in MODES:
        raise ValueError(f"progress must be one of {', '.join(MODES)}, got {progress!r}")
    if quiet:
        return "off"
    if progress == "auto":
        stream = stream or sys.stderr
        return "bar" if hasattr(stream, "isatty") and stream.isatty() else "off"
    return progress


class Progress:
    """Count work items; report as a bar, JSON lines or not at all.

    Use as a context manager; call :meth:`update` once per item. ``total`` may
    be ``None`` or 0 when unknown. The JSON mode writes at most one line per
    ``interval`` seconds, and a last line on a clean close.
    """

    def __init__(
        self,
        total: int | None,
        mode: str = "auto",
        unit: str = "frame",
        stream: TextIO | None = None,
        interval: float = 1.0,
    ):
        self.stream = stream or sys.stderr
        self.unit = unit
        self.mode = progress_mode(mode, stream=self.stream)
        self.total = total or None
        self.count = 0
        self.interval = interval
        self._start = self._last = time.monotonic()
        self._bar = None
        if self.mode == "bar":
            from tqdm import tqdm  # loaded only for a bar (about 20 ms)

            self._bar = tqdm(total=self.total, unit=unit, file=self.stream, dynamic_ncols=True)

    def update(self, n: int = 1) -> None:
        self.count += n
        if self._bar is not None:
            self._bar.update(n)
        elif self.mode == "json":
            now = time.monotonic()
            if now - self._last >= self.interval:
                self._last = now
                self._emit(now)

    def _emit(self, now: float) -> None:
        elapsed = now - self._start
        fps = self.count / elapsed if elapsed > 0 else 0.0
        eta = None
        if self.total and fps > 0:
            eta = round(max(self.total - self.count, 0) / fps, 1)
        line = {
            self.unit: self.count,
            "total": self.total,
            "fps" if self.unit == "frame" else "per_second": round(fps, 2),
            "time": round(elapsed, 1),
            "eta": eta,
        }
        print(json.dumps(line), file=self.stream, flush=True)

    def close(self, ok: bool = True) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        elif self.mode == "json" and ok:
            self._emit(time.monotonic())
            self.mode = "off"

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close(ok=exc_type is None)
