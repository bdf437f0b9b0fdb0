"""Rotations: ``circle``, ``vortex``, ``turn``, ``stir`` and ``oseen`` turn a point
about a centre C by an angle that depends only on its distance R from C (a
constant for ``turn``), which the rotation keeps: the angle computed at P' is
the angle at P and the inverse turns back exactly."""

from __future__ import annotations

import math

import numpy as np

from marblevideo.ops.base import (
    ALPHA,
    ANGLE,
    CENTER,
    FALLOFF,
    LAMBDA,
    RADIUS,
    OpDef,
    Param,
    Points,
    Values,
    direction,
)
from marblevideo.ops.gestures import Tool
from marblevideo.ops.series import SERIES_SLOTS, pack_series


def _rotate(sign: float, circle: bool):
    """theta = (alpha lambda / (d + lambda)) / R (0 at R = 0), d = |R - r| for a
    circle, R for a vortex; P' = C + rot(P - C, theta)."""

    def move(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
        cx, cy = v["center"]
        qx, qy = x - cx, y - cy
        big_r = np.hypot(qx, qy)
        d = np.abs(big_r - v["radius"]) if circle else big_r
        lam = v["lambda"]
        arc = v["alpha"] * lam / (d + lam)
        theta = sign * np.divide(arc, big_r, out=np.zeros_like(big_r), where=big_r > 0)
        c, s = np.cos(theta), np.sin(theta)
        return cx + (qx * c - qy * s), cy + (qx * s + qy * c)

    return move


#: A circle's and a vortex's packed floats (the kernel's op_vortex is op_circle):
#: theta in turns = turns / ((|R - r| + lambda) R).
ROTATION_SLOTS = ("cx", "cy", "radius", "turns", "lambda")


def pack_rotation(v: Values, lists: list) -> dict[str, float]:
    """cx, cy, r (0 for a vortex), alpha lambda / (2 pi), lambda."""
    (cx, cy), lam = v["center"], v["lambda"]
    turns = v["alpha"] * lam / (2 * math.pi)
    return {"cx": cx, "cy": cy, "radius": v.get("radius", 0.0), "turns": turns, "lambda": lam}


TURNS = ALPHA.but(help="Arc length of the motion; positive turns clockwise on screen.")

CIRCLE = OpDef(
    type="circle",
    help="A tine moved along a circle around `center`.",
    params=(
        CENTER,
        RADIUS.but(kind="nonnegative", help="Radius of the circle in canvas units, >= 0."),
        TURNS,
        LAMBDA,
    ),
    progress=(("alpha", "linear"),),
    slots=ROTATION_SLOTS,
    pack=pack_rotation,
    inverse=_rotate(-1.0, circle=True),
    forward=_rotate(1.0, circle=True),
    tools=(
        Tool(
            "centre",
            {
                "center": "a",
                "radius": {"positive": "len"},
                "alpha": {"positive": {"div": ["side", 3]}},
                "lambda": {"positive": {"div": ["side", 25]}},
            },
            label="radius",
        ),
    ),
    example={"type": "circle", "center": [40, 30], "radius": 15, "alpha": 30, "lambda": 8},
)

VORTEX = OpDef(
    type="vortex",
    help="A swirl that winds tighter towards its centre.",
    params=(CENTER, TURNS, LAMBDA),
    progress=(("alpha", "linear"),),
    slots=ROTATION_SLOTS,
    pack=pack_rotation,
    inverse=_rotate(-1.0, circle=False),
    forward=_rotate(1.0, circle=False),
    tools=(
        Tool(
            "centre",
            {
                "center": "a",
                "alpha": {"positive": {"mul": [2, "len"]}},
                "lambda": {"positive": {"div": ["len", 2]}},
            },
            label="alpha",
        ),
    ),
    example={"type": "vortex", "center": [40, 30], "alpha": 60, "lambda": 20},
)


def _turn(sign: float):
    """P' = C + rot(P - C, a) (sign 1) or its inverse, rot by -a (sign -1)."""

    def move(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
        cx, cy = v["center"]
        c, s = direction(sign * v["angle"])
        qx, qy = x - cx, y - cy
        return cx + (qx * c - qy * s), cy + (qx * s + qy * c)

    return move


def pack_turn(v: Values, lists: list) -> dict[str, float]:
    """cx, cy, cos a, sin a."""
    (cx, cy), (ca, sa) = v["center"], direction(v["angle"])
    return {"cx": cx, "cy": cy, "cos": ca, "sin": sa}


TURN = OpDef(
    type="turn",
    help="The tank turned about `center` by `angle` (the whole pattern rotates).",
    params=(
        CENTER,
        ANGLE.but(help="Rotation in degrees; positive turns clockwise on screen."),
    ),
    progress=(("angle", "linear"),),
    slots=("cx", "cy", "cos", "sin"),
    pack=pack_turn,
    inverse=_turn(-1.0),
    forward=_turn(1.0),
    tools=(Tool("centre", {"center": "a", "angle": "angle"}, label="angle"),),
    example={"type": "turn", "center": [40, 30], "angle": 35},
)


def _rotate_by(theta_of, sign: float):
    """P' = C + rot(P - C, theta(R)) (sign 1) or back (sign -1), theta 0 at R = 0."""

    def move(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
        cx, cy = v["center"]
        qx, qy = x - cx, y - cy
        big_r = np.hypot(qx, qy)
        theta = sign * theta_of(v, big_r)
        c, s = np.cos(theta), np.sin(theta)
        return cx + (qx * c - qy * s), cy + (qx * s + qy * c)

    return move


def _stir_theta(v: Values, big_r: np.ndarray) -> np.ndarray:
    """With ``alpha``: alpha * sum_i sign(r_i) exp(-|R - |r_i|| / L) / R, 0 at R = 0.
    With ``turn`` th: radians(th) * sum_i sign(r_i) exp(-|R - |r_i|| / (L |r_i|))."""
    total = np.zeros(np.shape(big_r))
    relative = "turn" in v
    for r in v["radii"]:
        falloff = v["falloff"] * abs(r) if relative else v["falloff"]
        total += math.copysign(1.0, r) * np.exp(-np.abs(big_r - abs(r)) / falloff)
    if relative:
        return math.radians(v["turn"]) * total
    total *= v["alpha"]
    return np.divide(total, big_r, out=np.zeros_like(total), where=big_r > 0)


#: A stir's packed floats: the centre, its turns (alpha / (2 pi) with ``alpha``,
#: th / 360 with ``turn``), 1/falloff, then its rings; ``relative`` is 1.0 for
#: the ``turn`` form (each ring its own fall-off L |r_i|), else 0.0.
STIR_SLOTS = ("cx", "cy", "turns", "inv_falloff", "relative", *SERIES_SLOTS)


def pack_stir(v: Values, lists: list) -> dict[str, float]:
    """cx, cy, turns, 1/falloff, and the rings. With ``alpha``: a series of |r_i|
    with coefficients sign(r_i) (where their data start in ``lists``, how many,
    whether in closed form: :mod:`marblevideo.ops.series`). With ``turn``: the n
    |r_i|, the n sign(r_i), then the n 1 / (L |r_i|), term by term."""
    radii = [float(r) for r in v["radii"]]
    signs = [math.copysign(1.0, r) for r in radii]
    (cx, cy), falloff = v["center"], v["falloff"]
    head = {"cx": cx, "cy": cy, "inv_falloff": 1.0 / falloff}
    if "turn" in v:
        at = len(lists)
        lists.extend(abs(r) for r in radii)
        lists.extend(signs)
        lists.extend(1.0 / (falloff * abs(r)) for r in radii)
        rings = {"series_at": at, "series_n": len(radii), "series_even": 0.0}
        return {**head, "turns": v["turn"] / 360.0, "relative": 1.0, **rings}
    series = pack_series([abs(r) for r in radii], signs, falloff, lists)
    return {**head, "turns": v["alpha"] / (2 * math.pi), "relative": 0.0, **series}


def check_stir(op, tracks) -> list:
    """``alpha`` or ``turn``: one of the two."""
    if "alpha" in op and "turn" in op:
        return [(["turn"], "give `alpha` (an arc length) or `turn` (an angle), not both")]
    if "alpha" not in op and "turn" not in op:
        return [([], "missing 'alpha' (or 'turn')")]
    return []


STIR = OpDef(
    type="stir",
    help="Tines moved along concentric circles around `center` (each ring its own way).",
    params=(
        CENTER,
        Param(
            "radii",
            "nonzeroList",
            "Radii of the rings in canvas units; a negative radius -r is a ring of "
            "radius r moved the other way.",
        ),
        TURNS.but(
            help="Arc length of the motion at a ring; positive turns clockwise on screen "
            "(or `turn`).",
            optional=True,
        ),
        Param(
            "turn",
            "number",
            "Angle in degrees the rings turn, instead of `alpha`; then `falloff` is a share of "
            "each ring's radius. Positive turns clockwise on screen.",
            "angle",
            optional=True,
        ),
        FALLOFF.but(
            help="Fall-off L > 0: the pull is alpha e^(-d/L) (canvas units); with `turn`, "
            "e^(-d/(L |r|)) (a share of each ring's radius)."
        ),
    ),
    progress=(("alpha", "linear"), ("turn", "linear")),
    slots=STIR_SLOTS,
    pack=pack_stir,
    inverse=_rotate_by(_stir_theta, -1.0),
    forward=_rotate_by(_stir_theta, 1.0),
    check=check_stir,
    tools=(
        Tool(
            "centre",
            {
                "center": "a",
                "radii": [
                    {"positive": {"div": ["len", 3]}},
                    {"positive": {"div": [{"mul": [2, "len"]}, 3]}},
                    {"positive": "len"},
                ],
                "alpha": {"positive": {"div": ["side", 6]}},
                "falloff": {"positive": {"div": ["len", 12]}},
            },
            label="alpha",
        ),
        Tool(
            "centre",
            {
                "center": "a",
                "radii": [{"positive": {"div": ["len", 2]}}, {"sub": [0, {"positive": "len"}]}],
                "turn": "angle",
                "falloff": 0.3,
            },
            name="stir-turn",
            label="turn",
        ),
    ),
    example={"type": "stir", "center": [40, 30], "radii": [8, -16, 24], "alpha": 9, "falloff": 3},
)


def _oseen_theta(v: Values, big_r: np.ndarray) -> np.ndarray:
    """G ((4 nu)^(3/4) + (2 pi R^2 / T)^(3/4))^(-4/3); 0 when T = 0."""
    g, nu, t = v["circulation"], v["viscosity"], v["time"]
    if t <= 0:
        return np.zeros(np.shape(big_r))
    return g * ((4 * nu) ** 0.75 + (2 * math.pi * big_r**2 / t) ** 0.75) ** (-4.0 / 3.0)


def pack_oseen(v: Values, lists: list) -> dict[str, float]:
    """cx, cy, G / (2 pi) (turns; 0 when T = 0), a = (4 nu)^(3/4), c = (2 pi / T)^(3/4),
    so that theta = G (a + c R^(3/2))^(-4/3)."""
    (cx, cy), t = v["center"], v["time"]
    if t <= 0:
        return {"cx": cx, "cy": cy, "turns": 0.0, "a": 1.0, "c": 0.0}
    g = v["circulation"] / (2 * math.pi)
    return {
        "cx": cx,
        "cy": cy,
        "turns": g,
        "a": (4 * v["viscosity"]) ** 0.75,
        "c": (2 * math.pi / t) ** 0.75,
    }


OSEEN = OpDef(
    type="oseen",
    help="A decaying viscous (Lamb-Oseen) vortex: a free vortex far out, a rigid turn at the core.",
    params=(
        CENTER,
        Param(
            "circulation",
            "number",
            "Circulation G in canvas units^2 per second; positive turns clockwise.",
            "area",
        ),
        Param("viscosity", "positive", "Viscosity nu > 0 in canvas units^2 per second.", "area"),
        Param("time", "nonnegative", "Seconds the vortex has acted, T >= 0.", "time"),
    ),
    progress=(("time", "linear"),),
    slots=("cx", "cy", "turns", "a", "c"),
    pack=pack_oseen,
    inverse=_rotate_by(_oseen_theta, -1.0),
    forward=_rotate_by(_oseen_theta, 1.0),
    tools=(
        Tool(
            "centre",
            {
                "center": "a",
                "circulation": {"positive": {"mul": [2, "pi", "len", "len"]}},
                "viscosity": {"positive": {"div": [{"mul": ["len", "len"]}, 4]}},
                "time": 1,
            },
            label="circulation",
        ),
    ),
    example={
        "type": "oseen",
        "center": [40, 30],
        "circulation": 4000,
        "viscosity": 300,
        "time": 2,
    },
)

OPS = (CIRCLE, VORTEX, TURN, STIR, OSEEN)
