"""A stroke drawn in time (format 1, revision 4): the steps of a ``stroke`` with
``times``, laid where the stylus has been.

L_i is the path's length up to given point i (a repeated point adds 0) and
l = L_last. The stylus' travel s(t) is 0 before times[0], l from times[last] on,
and in between L_i + (L_{i+1} - L_i) (t - times[i]) / (times[i+1] - times[i])
with i the largest index where times[i] <= t; the stylus is at S, the point at
arc length s. Steps lie at the fixed spacing d = w / 4 (Q_k at arc length k d):
step k is whole once (k + 1) d <= s (Q_k to Q_{k+1}, angle drag d 16 / (9 w)),
and the one step the stylus is inside is partial, Q_k to S (angle
drag |S - Q_k| 16 / (9 w)). Tines are offset along N0, the unit normal from Q_0
to the point at arc length min(s, d).

Everything here is computed point by point from the gesture so far, with
correctly rounded operations only (no hypot, no interpolation library), so a
stroke whose points are appended as they are drawn lays exactly the steps the
finished stroke lays at the time of its newest point. Conventions as
:mod:`marblevideo.ops.stroke`.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from marblevideo.ops.stepblocks import BLOCK_STEPS, block_rows, prefix_blocks

#: d = w / SPACING_PER_WIDTH: the fixed spacing of a timed stroke's steps.
SPACING_PER_WIDTH = 4.0


def arc_lengths(flat) -> np.ndarray:
    """L_i for every given point of ``flat`` (x0, y0, x1, y1, ...), from L_0 = 0."""
    pts = np.asarray(flat, np.float64).reshape(-1, 2)
    step = np.diff(pts, axis=0)
    seg = np.sqrt(step[:, 0] * step[:, 0] + step[:, 1] * step[:, 1])
    return np.concatenate(([0.0], np.cumsum(seg)))


@lru_cache(maxsize=64)
def path_lengths(flat: tuple[float, ...]) -> np.ndarray:
    """:func:`arc_lengths` of a path, computed once per path."""
    arc = arc_lengths(flat)
    arc.flags.writeable = False
    return arc


def turn_law(drag: float, width: float):
    """A step's angle for its length: theta = drag length 16 / (9 w) radians."""
    return lambda length: drag * length * 16.0 / (9.0 * width)


def travel(times, arc: np.ndarray, t: float) -> float:
    """s(t): the stylus' arc length at time ``t`` for point times ``times``."""
    if t < times[0]:
        return 0.0
    if t >= times[-1]:
        return float(arc[-1])
    i = bisect_right(times, t) - 1
    share = (t - times[i]) / (times[i + 1] - times[i])
    return float(arc[i] + (arc[i + 1] - arc[i]) * share)


def points_at(flat, arc: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The points (len(at), 2) at arc lengths ``at`` (0..l) along the polyline;
    a length at a given point gives that point exactly."""
    pts = np.asarray(flat, np.float64).reshape(-1, 2)
    last = len(pts) - 1
    i = np.clip(np.searchsorted(arc, at, side="right") - 1, 0, last)
    j = np.minimum(i + 1, last)
    span = arc[j] - arc[i]
    share = np.where(span > 0, (at - arc[i]) / np.where(span > 0, span, 1.0), 0.0)
    return pts[i] + (pts[j] - pts[i]) * share[:, None]


def whole_count(s: float, spacing: float) -> int:
    """How many steps are whole at travel ``s``: the largest W with W d <= s."""
    k = int(s // spacing)
    while (k + 1) * spacing <= s:
        k += 1
    while k > 0 and k * spacing > s:
        k -= 1
    return k


def _unit_normals(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit normals N = (-u.y, u.x) of the steps a -> b, and their lengths."""
    u = b - a
    length = np.sqrt(u[:, 0] * u[:, 0] + u[:, 1] * u[:, 1])
    u = u / length[:, None]
    return np.stack([-u[:, 1], u[:, 0]], axis=1), length


@dataclass(frozen=True)
class Whole:
    """Every whole step of a finished timed path (those with (k + 1) d <= l):
    ``centres`` (C + o N0) and ``halves`` ((w/2) N), (count * tines, 2) in forward
    order, their ``spacing`` d, ``n0`` (1, 2) the first step's unit normal (when
    count > 0), and ``lo``/``hi`` (count + 1, 2): the bounding box of the ends A, B
    of the first k steps (k = 0: empty)."""

    count: int
    tines: int
    spacing: float
    n0: np.ndarray
    centres: np.ndarray
    halves: np.ndarray
    lo: np.ndarray
    hi: np.ndarray


@lru_cache(maxsize=64)
def whole_steps(flat: tuple[float, ...], width: float, tines: tuple[float, ...]) -> Whole:
    """The whole steps of the path ``flat`` as finished (cached: laid once per
    stroke; a frame takes a prefix)."""
    arc = path_lengths(flat)
    d = width / SPACING_PER_WIDTH
    count = whole_count(float(arc[-1]), d)
    q = points_at(flat, arc, np.arange(count + 1) * d)
    normal, _ = _unit_normals(q[:-1], q[1:])
    mid = (q[:-1] + q[1:]) / 2
    offsets = np.asarray(tines, np.float64)[None, :, None] * normal[:1, None, :]
    centres = (mid[:, None, :] + offsets).reshape(-1, 2)
    halves = np.repeat(normal * (width / 2), len(tines), axis=0)
    ends = np.concatenate([centres + halves, centres - halves], axis=1).reshape(-1, len(tines), 4)
    lo = np.minimum(ends[:, :, 0:2].min(axis=1), ends[:, :, 2:4].min(axis=1))
    hi = np.maximum(ends[:, :, 0:2].max(axis=1), ends[:, :, 2:4].max(axis=1))
    lo = np.concatenate([[[np.inf, np.inf]], np.minimum.accumulate(lo, axis=0)])
    hi = np.concatenate([[[-np.inf, -np.inf]], np.maximum.accumulate(hi, axis=0)])
    for a in (centres, halves, lo, hi):
        a.flags.writeable = False
    return Whole(count, len(tines), d, normal[:1], centres, halves, lo, hi)


@dataclass(frozen=True)
class Partial:
    """The step the stylus is inside: its centres and halves (tines, 2) and its
    length d' (0: none)."""

    centres: np.ndarray
    halves: np.ndarray
    length: float


def partial_step(flat, width: float, tines, s: float, whole: Whole) -> Partial:
    """The partial step at travel ``s`` (Q_W to S, W = the whole steps at s), with
    N0 from Q_0 to the point at min(s, d)."""
    arc = path_lengths(tuple(flat))
    d = whole.spacing
    w_count = whole_count(s, d)
    offsets = np.asarray(tines, np.float64)[:, None]
    if s <= w_count * d:
        empty = np.zeros((0, 2))
        return Partial(empty, empty, 0.0)
    q, end = points_at(flat, arc, np.array([w_count * d, s]))
    normal, length = _unit_normals(q[None], end[None])
    n0 = whole.n0 if w_count > 0 else normal
    mid = (q + end) / 2
    centres = mid[None, :] + offsets * n0
    halves = np.repeat(normal * (width / 2), len(tines), axis=0)
    return Partial(centres, halves, float(length[0]))


def acting(flat, width: float, tines, s: float, angle) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The acting steps at travel ``s`` in forward order: centres, halves and
    turns (radians), with ``angle(length)`` a step's turn for its length."""
    whole = whole_steps(tuple(flat), width, tuple(tines))
    count = whole_count(s, whole.spacing) * whole.tines
    part = partial_step(flat, width, tines, s, whole)
    centres = np.concatenate([whole.centres[:count], part.centres])
    halves = np.concatenate([whole.halves[:count], part.halves])
    turns = np.concatenate(
        [np.full(count, angle(whole.spacing)), np.full(len(part.centres), angle(part.length))]
    )
    return centres, halves, turns


def times_faults(op) -> list:
    """A timed stroke's own faults: one time per point, none decreasing, and
    neither ``start`` nor ``end`` beside them."""
    times, points = op["times"], op["points"]
    if "start" in op or "end" in op:
        return [(["times"], "a stroke with `times` takes neither `start` nor `end`")]
    if len(times) != len(points):
        return [(["times"], f"needs one time per point ({len(points)}), got {len(times)}")]
    for i in range(1, len(times)):
        if times[i] < times[i - 1]:
            return [(["times", i], f"must not decrease: got {times[i]:g} after {times[i - 1]:g}")]
    return []


def step_total(length: float, width: float) -> int:
    """The step limit's count of a timed path along its length: floor(l / d) + 1."""
    return whole_count(length, width / SPACING_PER_WIDTH) + 1


@lru_cache(maxsize=64)
def _whole_rows(flat, width: float, tines, drag: float) -> tuple[float, ...]:
    """The kernel's data (cx, cy, hx, hy, angle per step) of every whole step."""
    whole = whole_steps(flat, width, tines)
    turn = np.full(len(whole.centres), turn_law(drag, width)(whole.spacing))
    return tuple(np.column_stack([whole.centres, whole.halves, turn]).ravel().tolist())


@lru_cache(maxsize=64)
def _whole_blocks(flat, width: float, tines) -> tuple[float, ...]:
    """The culling circles (:mod:`marblevideo.ops.stepblocks`) of every whole step."""
    whole = whole_steps(flat, width, tines)
    return tuple(block_rows(whole.centres, whole.halves, width).ravel().tolist())


def kernel_rows(flat, width: float, tines, drag: float, s: float) -> tuple[tuple, tuple, tuple]:
    """The kernel's data of the acting steps at travel ``s`` (the whole steps' a
    prefix of the finished stroke's, then the partial one), their blocks' culling
    circles, and their bounding box grown by ``width`` (empty when none acts)."""
    whole = whole_steps(flat, width, tines)
    done = whole_count(s, whole.spacing)
    part = partial_step(flat, width, tines, s, whole)
    if drag == 0 or (done == 0 and len(part.centres) == 0):
        return (), (), (1e30, 1e30, -1e30, -1e30)
    turn = np.full(len(part.centres), turn_law(drag, width)(part.length))
    rows = np.column_stack([part.centres, part.halves, turn])
    lo, hi = whole.lo[done], whole.hi[done]
    if len(part.centres):
        ends = np.concatenate([part.centres + part.halves, part.centres - part.halves])
        lo, hi = np.minimum(lo, ends.min(axis=0)), np.maximum(hi, ends.max(axis=0))
    count = done * whole.tines
    data = _whole_rows(flat, width, tines, drag)[: 5 * count]
    at = count - count % BLOCK_STEPS  # steps in the finished stroke's whole blocks
    centres = np.concatenate([whole.centres[at:count], part.centres])
    halves = np.concatenate([whole.halves[at:count], part.halves])
    blocks = prefix_blocks(_whole_blocks(flat, width, tines), at, centres, halves, width)
    box = (*(lo - width).tolist(), *(hi + width).tolist())
    return data + tuple(rows.ravel().tolist()), blocks, box
