"""What the live preview can change: the animation clock (pause, restart,
loop), bypass, mirror, and sliders for the recipe's constant numeric parameters.

- The clock is wall-clock time since the start (``t = 0`` at the first frame);
  paused, the design holds still while the source keeps flowing. Looping, it
  starts again at the recipe's end.
- Sliders: every op parameter that is a constant number (not keyframed) can be
  overridden; keyframed ones are shown as animated. Ranges follow each
  parameter's slider law (:func:`marblevideo.ops.slider_range`).
- Mirror flips the source left-right (selfie view) before marbling.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import replace

from marblevideo.errors import UsageError
from marblevideo.ops import NUMERIC_KINDS, op_def, slider_range
from marblevideo.recipe.keyframes import Track
from marblevideo.recipe.schema import LIMIT


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


def sliders(recipe, canvas: tuple[float, float] | None) -> list[dict]:
    """What the preview shows per op: each numeric parameter, adjustable if constant."""
    size = max(recipe.canvas or canvas or (1000.0, 1000.0))
    ops = []
    for op in recipe.ops:
        params = []
        for param in op_def(op.type).params:
            if param.kind not in NUMERIC_KINDS:
                continue
            name = param.name
            track = op.params[name]
            if track.varies:
                params.append({"name": name, "animated": True})
                continue
            v = float(track.keys[0].v[0])
            lo, hi, step = slider_range(param, v, size)
            params.append(
                {"name": name, "value": v, "min": lo, "max": hi, "step": step, "animated": False}
            )
        ops.append({"index": op.index, "type": op.type, "params": params})
    return ops


def with_overrides(recipe, overrides: dict[tuple[int, str], float]):
    """``recipe`` with constant parameters replaced: {(op index, name): value}."""
    if not overrides:
        return recipe
    ops = list(recipe.ops)
    for (i, name), value in overrides.items():
        params = dict(ops[i].params)
        params[name] = Track.constant(float(value))
        ops[i] = replace(ops[i], params=params)
    return replace(recipe, ops=tuple(ops))


class Controls:
    """The preview's controls, under one lock: :attr:`clock`, ``bypass``,
    ``mirror`` and slider ``overrides`` ({(op index, name): value});
    :attr:`version` counts changes of the overrides."""

    def __init__(self):
        self.clock = Clock()
        self.bypass = False
        self.mirror = False
        self.overrides: dict[tuple[int, str], float] = {}
        self.version = 0
        self._lock = threading.Lock()

    def snapshot(self) -> tuple[dict[tuple[int, str], float], bool, bool, int]:
        """(overrides, bypass, mirror, version) as they are now."""
        with self._lock:
            return dict(self.overrides), self.bypass, self.mirror, self.version

    def reset(self) -> None:
        """Drop every override (a reloaded recipe starts afresh)."""
        with self._lock:
            self.overrides.clear()
            self.version += 1

    def apply(self, request: dict, recipe) -> dict:
        """Apply a control request to the controls of ``recipe``; UsageError on a
        bad one. Returns the new state (:meth:`state`).

        Fields (all optional): ``paused`` (bool), ``restart`` (true), ``bypass``
        (bool), ``mirror`` (bool), ``param`` ({"op": i, "name": n, "value": v}),
        ``reset`` (true: drop every slider override), ``loop`` (bool: the clock
        starts again at the recipe's end, when it has one), ``time`` (seconds
        >= 0: the clock shows that time now).
        """
        if not isinstance(request, dict):
            raise UsageError("control: expected a JSON object")
        known = {"paused", "restart", "bypass", "mirror", "param", "reset", "loop", "time"}
        unknown = set(request) - known
        if unknown:
            raise UsageError(f"control: unknown field {sorted(unknown)[0]!r}")
        for name in ("paused", "bypass", "mirror", "restart", "reset", "loop"):
            if name in request and not isinstance(request[name], bool):
                raise UsageError(f"control: {name} must be true or false")
        seek = request.get("time")
        number = isinstance(seek, int | float) and not isinstance(seek, bool)
        if "time" in request and not (number and 0 <= seek <= LIMIT):
            raise UsageError(f"control: time must be seconds >= 0, got {seek!r}")
        param = request.get("param")
        if param is not None:
            key, value = _check_param(param, recipe)
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
                self.clock.loop_at = (recipe.end_time() or None) if request["loop"] else None
            if "time" in request:
                self.clock.seek(float(seek))
            if request.get("reset"):
                self.overrides.clear()
                self.version += 1
            if param is not None:
                self.overrides[key] = value
                self.version += 1
        return self.state()

    def state(self) -> dict:
        with self._lock:
            overrides = sorted(self.overrides.items())
            bypass, mirror = self.bypass, self.mirror
        return {
            "paused": self.clock.paused,
            "loop": self.clock.loop_at,
            "bypass": bypass,
            "mirror": mirror,
            "t": round(self.clock.now(), 3),
            "overrides": [{"op": i, "name": n, "value": v} for (i, n), v in overrides],
        }


def _check_param(param, recipe) -> tuple[tuple[int, str], float]:
    if not isinstance(param, dict) or set(param) != {"op", "name", "value"}:
        raise UsageError('control: param must be {"op": INDEX, "name": NAME, "value": NUMBER}')
    i, name, value = param["op"], param["name"], param["value"]
    ops = recipe.ops
    if not isinstance(i, int) or isinstance(i, bool) or not 0 <= i < len(ops):
        raise UsageError(f"control: param.op must be an op index 0..{len(ops) - 1}, got {i!r}")
    kind = op_def(ops[i].type).kinds.get(name)
    if kind not in NUMERIC_KINDS:
        raise UsageError(f"control: ops[{i}] ({ops[i].type}) has no numeric {name!r}")
    if ops[i].params[name].varies:
        raise UsageError(f"control: ops[{i}].{name} is animated (keys or a signal), not adjustable")
    ok = isinstance(value, int | float) and not isinstance(value, bool)
    if not ok or not math.isfinite(value) or abs(value) > LIMIT:
        raise UsageError(f"control: ops[{i}].{name}: expected a finite number, got {value!r}")
    if (kind == "positive" and value <= 0) or (kind == "nonnegative" and value < 0):
        raise UsageError(f"control: ops[{i}].{name}: must be {kind}, got {value}")
    return (i, name), float(value)
