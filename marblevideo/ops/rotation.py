"""Rotations: ``circle``, ``vortex`` and ``turn`` turn a point about a centre C
by an angle that depends only on its distance R from C (a constant for
``turn``), which the rotation keeps: the angle computed at P' is the angle at
P and the inverse turns back exactly."""

from __future__ import annotations

import math

import numpy as np

from marblevideo.ops.base import (
    ALPHA,
    ANGLE,
    CENTER,
    LAMBDA,
    RADIUS,
    OpDef,
    Points,
    Values,
    direction,
)


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


def pack_rotation(v: Values, lists: list) -> tuple[float, ...]:
    """cx, cy, r (0 for a vortex), alpha lambda / (2 pi), lambda: theta in turns."""
    radius = v.get("radius", 0.0)
    return (*v["center"], radius, v["alpha"] * v["lambda"] / (2 * math.pi), v["lambda"])


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
    pack=pack_rotation,
    inverse=_rotate(-1.0, circle=True),
    forward=_rotate(1.0, circle=True),
    example={"type": "circle", "center": [40, 30], "radius": 15, "alpha": 30, "lambda": 8},
)

VORTEX = OpDef(
    type="vortex",
    help="A swirl that winds tighter towards its centre.",
    params=(CENTER, TURNS, LAMBDA),
    progress=(("alpha", "linear"),),
    pack=pack_rotation,
    inverse=_rotate(-1.0, circle=False),
    forward=_rotate(1.0, circle=False),
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


def pack_turn(v: Values, lists: list) -> tuple[float, ...]:
    """cx, cy, cos a, sin a."""
    return (*v["center"], *direction(v["angle"]))


TURN = OpDef(
    type="turn",
    help="The tank turned about `center` by `angle` (the whole pattern rotates).",
    params=(
        CENTER,
        ANGLE.but(help="Rotation in degrees; positive turns clockwise on screen."),
    ),
    progress=(("angle", "linear"),),
    pack=pack_turn,
    inverse=_turn(-1.0),
    forward=_turn(1.0),
    example={"type": "turn", "center": [40, 30], "angle": 35},
)

OPS = (CIRCLE, VORTEX, TURN)
