"""Ink: ``drop`` (incompressible: the paint outside is pushed away, its area
preserved) and ``spray`` (a droplet that deforms nothing).

Where the contract is silent: the forward map of a drop at its very centre
(the paint at C is torn open) is C + (r, 0), the limit approached along +x;
its inverse at a point inside the drop (ink, not a moved point) is C; an ink
op of radius 0 (progress 0) is absent: identity, and no ink. An ink op holds
the points *strictly* inside its circle.
"""

from __future__ import annotations

import numpy as np

from marblevideo.ops.base import CENTER, COLOR, RADIUS, OpDef, Points, Values, identity
from marblevideo.ops.gestures import Tool


def contains(v: Values, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """|P - C| < r, strictly; nowhere for a radius of 0."""
    if v["radius"] <= 0:
        return np.zeros(np.shape(x), dtype=bool)
    cx, cy = v["center"]
    return np.hypot(x - cx, y - cy) < v["radius"]


#: An ink circle's packed floats: its centre, r^2 and colour (at COLOR_SLOTS).
CIRCLE_SLOTS = ("cx", "cy", "r2", "red", "green", "blue")
#: A drop's: its circle, then the sum of r^2 of the drops with its centre walked
#: just before it (a run of concentric drops), and 1 where it moves the point (the
#: last drop of its run walked; 0 for the others).
DROP_SLOTS = (*CIRCLE_SLOTS, "run_offset", "run_moves")
RUN_OFFSET, RUN_MOVES = DROP_SLOTS.index("run_offset"), DROP_SLOTS.index("run_moves")
R2 = CIRCLE_SLOTS.index("r2")


def pack_circle(v: Values, lists: list) -> dict[str, float]:
    """cx, cy, r^2, red, green, blue."""
    (cx, cy), (red, green, blue) = v["center"], v["color"]
    return {"cx": cx, "cy": cy, "r2": v["radius"] ** 2, "red": red, "green": green, "blue": blue}


def pack_drop(v: Values, lists: list) -> dict[str, float]:
    """:func:`pack_circle`, then a run of one (see :func:`link_concentric_drops`)."""
    return {**pack_circle(v, lists), "run_offset": 0.0, "run_moves": 1.0}


def link_concentric_drops(ops, rows: np.ndarray, walked: list[int] | None = None) -> None:
    """Link each run of adjacent drops with one centre in the packed ``rows``.

    Walked back through a run, a point's squared distance to the centre drops
    by each drop's r^2 in turn, and its direction from the centre is kept, so
    the run is one drop: each drop tests ink against |P' - C|^2 less the r^2 of
    the drops walked before it (RUN_OFFSET), and only the run's last drop
    walked moves the point, by all of them at once (RUN_MOVES): one square
    root for the run instead of one per drop, the same map. ``walked``: the
    indices of the ops the kernel walks (default: all); the others (skipped,
    as still) do not part a run.
    """
    order = list(range(len(ops))) if walked is None else walked
    n = len(order) - 1
    while n >= 0:
        i = order[n]
        if ops[i].type != "drop":
            n -= 1
            continue
        m = n
        while (
            m > 0
            and ops[order[m - 1]].type == "drop"
            and (ops[order[m - 1]]["center"] == ops[i]["center"])
        ):
            m -= 1
        offset = 0.0
        for k in reversed(order[m : n + 1]):  # walk order: i first
            rows[k, RUN_OFFSET], rows[k, RUN_MOVES] = offset, float(k == order[m])
            offset += rows[k, R2]
        n = m - 1


def drop_forward(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
    """P' = C + (P - C) sqrt(1 + r^2 / |P - C|^2); C + (r, 0) at P = C."""
    cx, cy = v["center"]
    r = float(v["radius"])
    shape = np.broadcast_shapes(np.shape(x), np.shape(y))
    qx = np.broadcast_to(np.asarray(x, np.float64), shape).reshape(-1) - cx
    qy = np.broadcast_to(np.asarray(y, np.float64), shape).reshape(-1) - cy
    k = qx * qx
    k += qy * qy
    at_c = k == 0
    if at_c.any():
        k[at_c] = 1.0  # any finite value: the point is placed below
    np.divide(r * r, k, out=k)
    k += 1.0
    np.sqrt(k, out=k)
    qx *= k
    qx += cx
    qy *= k
    qy += cy
    if at_c.any():
        qx[at_c], qy[at_c] = cx + r, cy
    return qx.reshape(shape), qy.reshape(shape)


def drop_inverse(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
    """P = C + (P' - C) sqrt(1 - r^2 / |P' - C|^2) outside the drop; C inside."""
    cx, cy = v["center"]
    r = float(v["radius"])
    qx, qy = x - cx, y - cy
    big_r = np.hypot(qx, qy)
    # sqrt(1 - r^2 / R^2) written as sqrt((R - r)(R + r)) / R: no cancellation near R = r.
    root = np.sqrt(np.maximum((big_r - r) * (big_r + r), 0.0))
    k = np.divide(root, big_r, out=np.zeros_like(big_r), where=big_r > 0)
    return cx + qx * k, cy + qy * k


DROP = OpDef(
    type="drop",
    help="Ink drop: paint outside is pushed away, its area preserved.",
    params=(CENTER, RADIUS, COLOR),
    progress=(("radius", "sqrt"),),
    slots=DROP_SLOTS,
    pack=pack_drop,
    inverse=drop_inverse,
    forward=drop_forward,
    contains=contains,
    tools=(
        Tool(
            "click",
            {
                "center": "a",
                "radius": {"positive": {"clicked": [{"mul": ["side", 0.06]}, "len"]}},
                "color": "color",
            },
            label="radius",
        ),
    ),
    example={"type": "drop", "center": [40, 30], "radius": 18, "color": "#1d3557"},
)

SPRAY = OpDef(
    type="spray",
    help="A droplet of ink that does not deform the pattern.",
    params=(CENTER, RADIUS, COLOR),
    progress=(("radius", "sqrt"),),
    slots=CIRCLE_SLOTS,
    pack=pack_circle,
    inverse=identity,
    forward=identity,
    contains=contains,
    tools=(
        Tool(
            "click",
            {
                "center": "a",
                "radius": {"positive": {"clicked": [{"mul": ["side", 0.03]}, "len"]}},
                "color": "color",
            },
            label="radius",
        ),
    ),
    example={"type": "spray", "center": [60, 20], "radius": 9, "color": [233, 196, 106]},
)

OPS = (DROP, SPRAY)
