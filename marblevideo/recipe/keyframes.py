"""Keyframe tracks: a parameter value that is constant or keyed in time.

Conventions (docs/recipe-format.md, "Keyframe tracks"): times in seconds,
strictly increasing; the ``ease`` of key i shapes the segment that *leaves*
it, v = v_i + (v_{i+1} - v_i) * ease_i(u) with u = (t - t_i) / (t_{i+1} - t_i),
component by component. Before the first key a track holds the first value,
after the last key the last value. At a key's time exactly, the value is that
key's value.

Values are stored as tuples of floats (1 component for numbers, 2 for points,
3 for colors in 0..255); :meth:`Track.at` returns a float for numbers.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass

import numpy as np

#: An ease: a name of :data:`EASE_NAMES` or CSS cubic-bezier control points (x1, y1, x2, y2).
Ease = str | tuple[float, float, float, float]

#: The named eases that are CSS cubic-beziers.
BEZIERS: dict[str, tuple[float, float, float, float]] = {
    "ease-in": (0.42, 0.0, 1.0, 1.0),
    "ease-out": (0.0, 0.0, 0.58, 1.0),
    "ease-in-out": (0.42, 0.0, 0.58, 1.0),
}
EASE_NAMES: tuple[str, ...] = ("linear", "hold", *BEZIERS)

_NEWTON_STEPS = 8
_BISECT_STEPS = 60
_TOL = 1e-12


def _bezier_coefficients(p1: float, p2: float) -> tuple[float, float, float]:
    """(a, b, c) with B(s) = ((a s + b) s + c) s for control values 0, p1, p2, 1."""
    c = 3.0 * p1
    b = 3.0 * (p2 - p1) - c
    return 1.0 - c - b, b, c


def cubic_bezier(
    x1: float, y1: float, x2: float, y2: float, u: float | np.ndarray
) -> float | np.ndarray:
    """CSS ``cubic-bezier(x1, y1, x2, y2)`` at progress ``u`` (clipped to [0, 1]).

    Solves x(s) = u for the curve parameter s (Newton from s = u, then
    bisection for whatever is not pinned to within 1e-12 in s; x is monotonic
    since x1, x2 lie in [0, 1]) and returns y(s). Accepts scalars or arrays.
    """
    ax, bx, cx = _bezier_coefficients(x1, x2)
    ay, by, cy = _bezier_coefficients(y1, y2)
    uu = np.clip(np.atleast_1d(np.asarray(u, dtype=np.float64)), 0.0, 1.0)

    def x_of(s: np.ndarray) -> np.ndarray:
        return ((ax * s + bx) * s + cx) * s

    s = uu.copy()
    for _ in range(_NEWTON_STEPS):
        slope = (3.0 * ax * s + 2.0 * bx) * s + cx
        steep = np.abs(slope) > 1e-9
        s = np.clip(s - np.where(steep, (x_of(s) - uu) / np.where(steep, slope, 1.0), 0.0), 0, 1)
    # Converged when u is bracketed within _TOL in s (a tolerance on x alone fails where
    # x is flat and y steep, e.g. x1 = x2 = 0 near u = 0).
    stuck = (x_of(s - _TOL) > uu) | (x_of(s + _TOL) < uu)
    if np.any(stuck):
        lo, hi, target = np.zeros_like(uu[stuck]), np.ones_like(uu[stuck]), uu[stuck]
        for _ in range(_BISECT_STEPS):
            mid = 0.5 * (lo + hi)
            below = x_of(mid) < target
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        s[stuck] = 0.5 * (lo + hi)
    y = ((ay * s + by) * s + cy) * s
    return float(y[0]) if np.ndim(u) == 0 else y.reshape(np.shape(u))


def ease(spec: Ease, u: float | np.ndarray) -> float | np.ndarray:
    """The eased fraction for segment progress ``u`` in [0, 1] (scalar or array).

    ``linear`` is u; ``hold`` is 0 until u reaches 1; the other names and
    4-tuples are cubic-beziers.
    """
    if spec == "linear":
        return u
    if spec == "hold":
        return np.where(np.asarray(u) >= 1.0, 1.0, 0.0) if np.ndim(u) else float(u >= 1.0)
    x1, y1, x2, y2 = BEZIERS[spec] if isinstance(spec, str) else spec
    return cubic_bezier(x1, y1, x2, y2, u)


@dataclass(frozen=True)
class Key:
    """One keyframe: value ``v`` (tuple of floats) at time ``t``; ``ease`` leaves it."""

    t: float
    v: tuple[float, ...]
    ease: Ease = "linear"


@dataclass(frozen=True)
class Track:
    """A parameter's value over time: ``keys`` sorted by strictly increasing ``t``.

    A constant is one key with ``keyed`` False (it has no key times). ``scalar``
    tells :meth:`at` to return a float rather than a 1-tuple.
    """

    keys: tuple[Key, ...]
    scalar: bool
    keyed: bool = True

    @classmethod
    def constant(cls, value: float | tuple[float, ...]) -> Track:
        """A track that is ``value`` at every time."""
        if isinstance(value, tuple):
            return cls((Key(0.0, tuple(float(c) for c in value)),), scalar=False, keyed=False)
        return cls((Key(0.0, (float(value),)),), scalar=True, keyed=False)

    @property
    def key_times(self) -> tuple[float, ...]:
        """Times of the keys; empty for a constant."""
        return tuple(k.t for k in self.keys) if self.keyed else ()

    @property
    def varies(self) -> bool:
        """Whether the value changes with time (a keyed track; a signal's varies too)."""
        return self.keyed

    def at(self, t: float, signals: object = None) -> float | tuple[float, ...]:
        """The value at time ``t`` (seconds); ``signals`` is ignored (keys follow
        no signal: see :class:`~marblevideo.recipe.signals.SignalTrack`)."""
        keys = self.keys
        i = bisect_right([k.t for k in keys], t) - 1
        if i < 0:
            value = keys[0].v
        elif i >= len(keys) - 1:
            value = keys[-1].v
        else:
            a, b = keys[i], keys[i + 1]
            w = float(ease(a.ease, (t - a.t) / (b.t - a.t)))
            value = tuple(va + (vb - va) * w for va, vb in zip(a.v, b.v, strict=True))
        return value[0] if self.scalar else value
