"""Free-hand strokes (format 1, revision 3): ``stroke``, a stylus (or a rigid comb
of styluses) drawn along a polyline as a train of small vortex-pair steps.

The path of length l is cut into n = ceil(4 l / w) steps of length d = l / n
(Q_k at arc length k d). Step k of tine o turns the fluid about
A = C_k + o N0 + (w/2) N_k by +theta e_k g(|P - A|), then about
B = C_k + o N0 - (w/2) N_k by -theta e_k g(|P1 - B|), with C_k the step's
midpoint, N_k its unit normal, N0 the first step's, g(r) = (1 - r^2/w^2)^2
inside w (else 0) and theta = drag d 16 / (9 w) radians. Each turn's angle
depends only on the distance to its centre, which the turn keeps, so turning
back in reverse order inverts a step exactly, and every step preserves area.
Nothing farther than w from every A and B moves, so a step is skipped for a
point farther than 3w/2 from its centre C (one squared distance).

Progress is the stylus' travel: at progress p step k acts with
e_k = clamp(p n - k, 0, 1), so only the first ceil(p n) steps act.

With ``times`` (revision 4) the stylus is where the gesture was at time t and
the steps lie at the fixed spacing w / 4 instead (:mod:`marblevideo.ops.stylus`):
``values["stylus"]`` holds its travel s(t) (set by :func:`clock`), scaled by the
progress (``heal``). Either way a frame's acting steps come from
:func:`acting_steps`, which the maps and the kernel's data share.

Conventions as :mod:`marblevideo.ops.base`: canvas units, origin top-left,
y down; positive turns are clockwise on screen. ``points`` reach the maps
flattened, (x0, y0, x1, y1, ...).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from marblevideo.ops.base import OpDef, Param, Points, Values
from marblevideo.ops.gestures import Setting, Tool
from marblevideo.ops.stepblocks import BLOCK_STEPS, block_rows, prefix_blocks
from marblevideo.ops.stylus import (
    acting,
    kernel_rows,
    path_lengths,
    step_total,
    times_faults,
    travel,
    turn_law,
)

#: Most points in a stroke's path, tines in its comb, and steps (along the path
#: times tines) in one stroke.
MAX_POINTS, MAX_TINES, MAX_STEPS = 4096, 64, 200_000
#: ``drag`` must lie in -DRAG_LIMIT..DRAG_LIMIT.
DRAG_LIMIT = 4.0
#: Defaults of the optional parameters.
DEFAULT_WIDTH, DEFAULT_DRAG = 24, 1
#: Floats per step in the kernel's data: cx, cy, hx, hy, the angle in radians.
STEP_FLOATS = 5
#: Steps per width: n = ceil(STEPS_PER_WIDTH l / w).
STEPS_PER_WIDTH = 4.0


def path_points(flat) -> np.ndarray:
    """The path as an (m, 2) float64 array, repeated consecutive points dropped."""
    pts = np.asarray(flat, np.float64).reshape(-1, 2)
    if len(pts) < 2:
        return pts
    keep = np.ones(len(pts), dtype=bool)
    keep[1:] = np.any(pts[1:] != pts[:-1], axis=1)
    return pts[keep]


def step_count(length: float, width: float) -> int:
    """n = ceil(4 l / w), at least 1."""
    return max(1, math.ceil(STEPS_PER_WIDTH * length / width))


@dataclass(frozen=True)
class Layout:
    """Where a stroke's steps lie, independent of ``drag`` and progress: ``n``
    steps along the path of length ``step`` each, ``tines`` of them per step;
    ``centres`` and ``halves`` (n * tines, 2) in forward order (step-major):
    each step's C + o N0 and (w/2) N, so A = centre + half, B = centre - half;
    ``blocks`` the steps' culling circles (:mod:`marblevideo.ops.stepblocks`)."""

    n: int
    step: float
    tines: int
    centres: np.ndarray
    halves: np.ndarray
    blocks: tuple[float, ...]


@lru_cache(maxsize=64)
def layout(flat: tuple[float, ...], width: float, tines: tuple[float, ...]) -> Layout:
    """The steps of a path (``flat`` points), built once per stroke (cached: a
    static stroke is laid out once however many frames it is packed for)."""
    pts = path_points(flat)
    seg = np.hypot(*np.diff(pts, axis=0).T)
    arc = np.concatenate(([0.0], np.cumsum(seg)))
    n = step_count(float(arc[-1]), width)
    s = np.linspace(0.0, arc[-1], n + 1)
    q = np.stack([np.interp(s, arc, pts[:, 0]), np.interp(s, arc, pts[:, 1])], axis=1)
    u = np.diff(q, axis=0)
    u /= np.hypot(u[:, 0], u[:, 1])[:, None]
    normal = np.stack([-u[:, 1], u[:, 0]], axis=1)
    mid = (q[:-1] + q[1:]) / 2
    offsets = np.asarray(tines, np.float64)[None, :, None] * normal[0]
    centres = (mid[:, None, :] + offsets).reshape(-1, 2)
    halves = np.repeat(normal * (width / 2), len(tines), axis=0)
    for a in (centres, halves):
        a.flags.writeable = False
    blocks = tuple(block_rows(centres, halves, width).ravel().tolist())
    return Layout(n, float(arc[-1]) / n, len(tines), centres, halves, blocks)


def layout_of(v: Values) -> Layout:
    return layout(tuple(v["points"]), float(v["width"]), tuple(v["tines"]))


def angles(v: Values, lay: Layout) -> np.ndarray:
    """Each step's theta e_k in radians (n * tines, forward order)."""
    theta = turn_law(v["drag"], v["width"])(lay.step)
    e = np.clip(v.get("travel", 1.0) * lay.n - np.arange(lay.n), 0.0, 1.0)
    return np.repeat(theta * e, lay.tines)


def timed_travel(v: Values) -> float:
    """A timed stroke's travel s(t) h(t): its stylus scaled by the progress."""
    return float(v["stylus"]) * float(v.get("travel", 1.0))


def acting_steps(v: Values) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The steps of one instant in forward order (step-major): centres, halves
    and turns theta e_k (radians; a revision-3 stroke's may be 0)."""
    w = float(v["width"])
    if "times" in v:
        law = turn_law(float(v["drag"]), w)
        return acting(v["points"], w, v["tines"], timed_travel(v), law)
    lay = layout_of(v)
    return lay.centres, lay.halves, angles(v, lay)


def clock(values: dict, t: float) -> dict:
    """A timed stroke's stylus travel s(t) at time ``t`` (in place)."""
    if "times" in values:
        arc = path_lengths(tuple(values["points"]))
        values["stylus"] = travel(values["times"], arc, t)
    return values


def _turn(x, y, cx, cy, angle, inv_w2) -> None:
    """(x, y) turned about (cx, cy) by g(r), g = (1 - r^2/w^2)^2 inside w, in place; others kept."""
    qx, qy = x - cx, y - cy
    g = 1.0 - (qx * qx + qy * qy) * inv_w2
    inside = np.flatnonzero(g > 0)
    if inside.size:
        qx, qy, a = qx[inside], qy[inside], angle * g[inside] ** 2
        c, s = np.cos(a), np.sin(a)
        x[inside], y[inside] = cx + qx * c - qy * s, cy + qx * s + qy * c


#: Steps walked together over the points in their joint reach (see :func:`_walk`).
BLOCK = 32


def _walk(sign: float):
    """The forward map (sign 1: steps in order, A then B) or the inverse (sign -1:
    steps in reverse, B by +angle then A by -angle). Steps go in blocks of BLOCK:
    only the points inside the block's reach (the box of its centres grown by
    3w/2) are walked through it, each step on those within 3w/2 of its centre;
    a step keeps a point it moves within its reach, so the box holds it."""

    def move(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
        centres, halves, turns = acting_steps(v)
        reach = 1.5 * float(v["width"])
        shape = np.broadcast(x, y).shape
        x = np.array(np.broadcast_to(x, shape), np.float64).ravel()
        y = np.array(np.broadcast_to(y, shape), np.float64).ravel()
        order = np.flatnonzero(turns)
        order = order if sign > 0 else order[::-1]
        for at in range(0, len(order), BLOCK):
            block = order[at : at + BLOCK]
            lo = centres[block].min(axis=0) - reach
            hi = centres[block].max(axis=0) + reach
            inside = np.flatnonzero((x >= lo[0]) & (x <= hi[0]) & (y >= lo[1]) & (y <= hi[1]))
            if inside.size:
                steps = (centres, halves, turns)
                x[inside], y[inside] = _steps(steps, block, sign, v["width"], x[inside], y[inside])
        return x.reshape(shape), y.reshape(shape)

    return move


def _steps(steps, block, sign: float, width: float, x, y) -> Points:
    """Steps ``block`` of ``steps`` (centres, halves, turns; in the order given) on
    the points (x, y), each on those within 3w/2 of its centre."""
    inv_w2, reach2 = 1.0 / (width * width), (1.5 * width) ** 2
    centres, halves, turns = steps
    for j in block.tolist():
        (cx, cy), (hx, hy), turn = centres[j].tolist(), halves[j].tolist(), float(turns[j])
        dx, dy = x - cx, y - cy
        near = np.flatnonzero(dx * dx + dy * dy < reach2)
        if near.size == 0:
            continue
        px, py = x[near], y[near]
        first, second = ((cx + hx, cy + hy), (cx - hx, cy - hy))[:: int(sign)]
        _turn(px, py, *first, turn, inv_w2)
        _turn(px, py, *second, -turn, inv_w2)
        x[near], y[near] = px, py
    return x, y


@lru_cache(maxsize=64)
def _rows(flat, width: float, tines, drag: float, travel: float) -> tuple[tuple, tuple, tuple]:
    """The kernel's data of the acting steps (a prefix: e_k > 0 for k < p n), their
    blocks' culling circles (:mod:`marblevideo.ops.stepblocks`), and their bounding
    box grown by ``width`` (empty when none acts)."""
    v = {"points": flat, "width": width, "tines": tines, "drag": drag, "travel": travel}
    lay = layout_of(v)
    turns = angles(v, lay)
    count = len(turns) if drag == 0 else int(np.count_nonzero(turns))
    if drag == 0 or count == 0:
        return (), (), (1e30, 1e30, -1e30, -1e30)
    c, h = lay.centres[:count], lay.halves[:count]
    rows = np.column_stack([c, h, turns[:count]])
    at = count - count % BLOCK_STEPS  # steps in the whole stroke's whole blocks
    blocks = prefix_blocks(lay.blocks, at, c[at:], h[at:], width)
    ends = np.concatenate([c + h, c - h])
    lo, hi = ends.min(axis=0) - width, ends.max(axis=0) + width
    return tuple(rows.ravel().tolist()), blocks, (*lo.tolist(), *hi.tolist())


#: A stroke's packed floats (:func:`pack`).
SLOTS = ("steps_at", "steps_n", "inv_w2", "reach2", "xmin", "ymin", "xmax", "ymax", "block")


def pack(v: Values, lists: list) -> dict[str, float]:
    """Where the steps start in ``lists``, how many, 1/w^2, (3w/2)^2 (a step's
    reach from its centre), the bounding box xmin, ymin, xmax, ymax of every
    acting step's reach, and the steps per culling block. Each step: cx, cy, hx,
    hy, theta e_k (radians, at most 16/9: the kernel's polynomials need no range
    reduction); after the steps, each block's circle: cx, cy, r^2."""
    w = float(v["width"])
    flat, tines, drag = tuple(v["points"]), tuple(v["tines"]), float(v["drag"])
    if "times" in v:
        rows, blocks, box = kernel_rows(flat, w, tines, drag, timed_travel(v))
    else:
        rows, blocks, box = _rows(flat, w, tines, drag, float(v.get("travel", 1.0)))
    at = len(lists)
    lists.extend(rows + blocks)
    steps = {"steps_at": at, "steps_n": len(rows) // STEP_FLOATS, "block": BLOCK_STEPS}
    reach = {"inv_w2": 1.0 / (w * w), "reach2": (1.5 * w) ** 2}
    return {**steps, **reach, **dict(zip(("xmin", "ymin", "xmax", "ymax"), box, strict=True))}


def _drag_faults(track) -> list:
    for i, key in enumerate(track.keys):
        value = key.v[0]
        if not -DRAG_LIMIT <= value <= DRAG_LIMIT:
            path = ["drag", "keys", i, "v"] if track.keyed else ["drag"]
            return [(path, f"must be in -4..4, got {value:g}")]
    return []


def check(op, tracks) -> list:
    """At least 2 distinct points and a path of length > 0, ``times`` (one per
    point, none decreasing, no ``start``/``end``), at most MAX_TINES tines,
    ``drag`` in -4..4 at every key, at most MAX_STEPS steps."""
    if "times" in op and (faults := times_faults(op)):
        return faults
    pts = path_points([c for point in op["points"] for c in point])
    if len(pts) < 2:
        return [(["points"], f"needs at least 2 distinct points, got {len(pts)}")]
    length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
    if not length > 0:
        return [(["points"], "the path has length 0")]
    tines = op.get("tines", [0.0])
    if len(tines) > MAX_TINES:
        return [(["tines"], f"must hold at most {MAX_TINES} tines, got {len(tines)}")]
    faults = _drag_faults(tracks["drag"])
    if faults:
        return faults
    width = float(op.get("width", DEFAULT_WIDTH))
    n = step_total(length, width) if "times" in op else step_count(length, width)
    if n * len(tines) > MAX_STEPS:
        return [
            (
                [],
                f"a stroke of {n * len(tines)} steps ({n} along the path x {len(tines)} "
                f"tines), more than {MAX_STEPS}: widen `width` or shorten the path",
            )
        ]
    return []


def settle(values: dict) -> dict:
    """``drag`` held to -4..4 where an overshooting ease leaves it between keys."""
    values["drag"] = max(-DRAG_LIMIT, min(DRAG_LIMIT, values["drag"]))
    return values


#: The curl tool's loop radius: a thirtieth of the canvas for a click, else the drag.
_CURL_RADIUS = {"max": [0.5, {"round1": {"clicked": [{"div": ["side", 30]}, "len"]}}]}

STROKE = OpDef(
    type="stroke",
    help="A stylus (or a comb of styluses) drawn along a free-hand path `points`.",
    params=(
        Param(
            "points",
            "pointList",
            f"The path [[x, y], ...] in the order drawn, 2..{MAX_POINTS} points (canvas units).",
        ),
        Param(
            "width",
            "positive",
            "Breadth of the ink carried along (canvas units); nothing farther from the path moves.",
            "length",
            optional=True,
            default=DEFAULT_WIDTH,
            keyable=False,
        ),
        Param(
            "drag",
            "number",
            "-4..4: how far ink at the stylus follows it, as a share of its travel; "
            "negative pushes it back.",
            "share",
            optional=True,
            default=DEFAULT_DRAG,
        ),
        Param(
            "tines",
            "numberList",
            f"1..{MAX_TINES} offsets of a comb's styluses along the first step's normal "
            "(canvas units).",
            optional=True,
            default=[0],
        ),
        Param(
            "times",
            "timeList",
            "Seconds, one per point, non-decreasing: when the stylus passed each point "
            "(a gesture replayed as drawn; takes neither start nor end).",
            optional=True,
        ),
    ),
    travels=True,
    clock=clock,
    slots=SLOTS,
    tools=(
        Tool(
            "path", {"points": "path", "width": {"round1": "setting.width"}, "drag": "setting.drag"}
        ),
        Tool(
            "path",
            {
                "points": "path",
                "width": {"round1": "setting.width"},
                "drag": "setting.drag",
                "tines": {"round1": {"centred": ["setting.tines", {"round1": "setting.spacing"}]}},
            },
            name="comb-stroke",
        ),
        # the French curl's gesture: a click draws a small closed loop; a drag sets its radius
        Tool(
            "click",
            {
                "points": {"loop": ["a", _CURL_RADIUS]},
                "width": {"round1": _CURL_RADIUS},
                "drag": "setting.drag",
            },
            name="curl",
        ),
    ),
    settings=(
        Setting("width", "the strokes' width", {"div": ["side", 12]}, positive=True),
        Setting("drag", "their drag (-4..4)", 1, initial="1", low=-4, high=4),
        Setting(
            "tines", "the comb stroke's tines", 5, initial="5", positive=True, high=64, integer=True
        ),
        Setting("spacing", "and their spacing", {"div": ["side", 16]}, positive=True),
    ),
    pack=pack,
    chained=True,
    inverse=_walk(-1.0),
    forward=_walk(1.0),
    check=check,
    settle=settle,
    example={
        "type": "stroke",
        "points": [[10, 40], [30, 18], [52, 36], [70, 16]],
        "width": 12,
        "drag": 1.5,
        "tines": [-5, 5],
    },
)

OPS = (STROKE,)
