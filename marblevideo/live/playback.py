"""How a live session plays (``POST /control``): the animation clock (pause,
restart, seek, loop), bypass and mirror. The recipe itself is edited through the
designer's API (``PUT /api/recipe``, :mod:`marblevideo.design.live`).

- The clock is wall-clock time since the start (``t = 0`` at the first frame);
  paused, the design holds still while the source keeps flowing. Looping, it
  starts again at the recipe's end.
- Bypass shows the source unmarbled; mirror flips it left-right (selfie view)
  before marbling.
"""

from __future__ import annotations

import threading
import time

from marblevideo.errors import UsageError
from marblevideo.recipe.schema import LIMIT

#: The fields of a control request.
FIELDS = ("paused", "restart", "bypass", "mirror", "loop", "time")


class Clock:
    """Wall-clock seconds since the start; pausable and restartable."""

    def __init__(self):
        self._lock = threading.Lock()
        self._origin = time.monotonic()
        self._paused_at: float | None = None
        self.loop_at: float | None = None  # seconds after which it starts again

    @property
    def paused(self) -> bool:
        return self._paused_at is not None

    def now(self) -> float:
        with self._lock:
            ref = self._paused_at if self._paused_at is not None else time.monotonic()
            t = ref - self._origin
            return t % self.loop_at if self.loop_at else t

    def pause(self, paused: bool = True) -> None:
        with self._lock:
            now = time.monotonic()
            if paused and self._paused_at is None:
                self._paused_at = now
            elif not paused and self._paused_at is not None:
                self._origin += now - self._paused_at
                self._paused_at = None

    def seek(self, t: float) -> None:
        """Show time ``t`` now (paused or running, it goes on from there)."""
        with self._lock:
            ref = self._paused_at if self._paused_at is not None else time.monotonic()
            self._origin = ref - t

    def restart(self) -> None:
        with self._lock:
            self._origin = time.monotonic()
            if self._paused_at is not None:
                self._paused_at = self._origin


class Playback:
    """How the session plays, under one lock: :attr:`clock`, ``bypass`` and ``mirror``."""

    def __init__(self):
        self.clock = Clock()
        self.bypass = False
        self.mirror = False
        self._lock = threading.Lock()

    def snapshot(self) -> tuple[bool, bool]:
        """(bypass, mirror) as they are now."""
        with self._lock:
            return self.bypass, self.mirror

    def apply(self, request: dict, recipe) -> dict:
        """Apply a control request to the playback of ``recipe``; UsageError on a
        bad one. Returns the new state (:meth:`state`).

        Fields (all optional): ``paused`` (bool), ``restart`` (true), ``bypass``
        (bool), ``mirror`` (bool), ``loop`` (bool: the clock starts again at the
        recipe's end, when it has one), ``time`` (seconds >= 0: the clock shows
        that time now).
        """
        seek = _checked(request)
        with self._lock:
            if "paused" in request:
                self.clock.pause(request["paused"])
            if request.get("restart"):
                self.clock.restart()
            if "bypass" in request:
                self.bypass = request["bypass"]
            if "mirror" in request:
                self.mirror = request["mirror"]
            if "loop" in request:
                self.clock.loop_at = (recipe.settled_time() or None) if request["loop"] else None
            if seek is not None:
                self.clock.seek(seek)
        return self.state()

    def state(self) -> dict:
        with self._lock:
            bypass, mirror = self.bypass, self.mirror
        return {
            "paused": self.clock.paused,
            "loop": self.clock.loop_at,
            "bypass": bypass,
            "mirror": mirror,
            "t": round(self.clock.now(), 3),
        }


def _checked(request) -> float | None:
    """Refuse a bad control request (UsageError, one line); its ``time``, if any."""
    if not isinstance(request, dict):
        raise UsageError("control: expected a JSON object")
    if "param" in request:  # the old live page's slider overrides
        raise UsageError("control: param is gone: edit the recipe (PUT /api/recipe)")
    unknown = set(request) - set(FIELDS)
    if unknown:
        raise UsageError(f"control: unknown field {sorted(unknown)[0]!r}")
    for name in ("paused", "bypass", "mirror", "restart", "loop"):
        if name in request and not isinstance(request[name], bool):
            raise UsageError(f"control: {name} must be true or false")
    if "time" not in request:
        return None
    seek = request["time"]
    number = isinstance(seek, int | float) and not isinstance(seek, bool)
    if not (number and 0 <= seek <= LIMIT):
        raise UsageError(f"control: time must be seconds >= 0, got {seek!r}")
    return float(seek)
