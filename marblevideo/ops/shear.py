"""Shears: ``tine``, ``comb`` and ``wave`` move a point along a fixed direction by
a shift that depends only on its coordinate across that direction, so the
shift computed at P' equals the shift at P and the inverse subtracts it
exactly."""

from __future__ import annotations

import math

import numpy as np

from marblevideo.ops.base import (
    ALPHA,
    ANGLE,
    LAMBDA,
    POINT,
    OpDef,
    Param,
    Points,
    Values,
    direction,
)


def _tine_shift(v: Values, x: np.ndarray, y: np.ndarray, comb: bool):
    """Shift along M, and M: alpha lambda / (d + lambda), d = |(P - A) . N| (for a
    comb the distance to the nearest tine, d' = s/2 - |fmod(d, s) - s/2|)."""
    mx, my = direction(v["angle"])
    ax, ay = v["point"]
    d = np.abs((x - ax) * -my + (y - ay) * mx)  # |(P - A) . N|
    if comb:
        s = v["spacing"]
        m = d - s * np.floor(d / s)  # floor-based mod, in [0, s)
        d = s / 2 - np.abs(m - s / 2)  # distance to the nearest tine
    lam = v["lambda"]
    return v["alpha"] * lam / (d + lam), mx, my


def _wave_shift(v: Values, x: np.ndarray, y: np.ndarray, comb: bool = False):
    """Shift along (cos t, sin t): amplitude sin(2 pi v / wavelength + phase) with
    v = P . (sin t, -cos t)."""
    mx, my = direction(v["angle"])
    across = x * my - y * mx  # P . (sin t, -cos t)
    phase = math.radians(v["phase"])
    return v["amplitude"] * np.sin(2 * math.pi * across / v["wavelength"] + phase), mx, my


def _shear(shift, sign: float, comb: bool = False):
    def move(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
        s, mx, my = shift(v, x, y, comb)
        return x + sign * s * mx, y + sign * s * my

    return move


def pack_tine(v: Values, lists: list) -> tuple[float, ...]:
    """ax, ay, M, N, alpha lambda, lambda; for a comb then spacing, 1/spacing, spacing/2."""
    ca, sa = direction(v["angle"])
    row = (*v["point"], ca, sa, -sa, ca, v["alpha"] * v["lambda"], v["lambda"])
    if "spacing" in v:
        s = v["spacing"]
        row += (s, 1.0 / s, s / 2.0)
    return row


def pack_wave(v: Values, lists: list) -> tuple[float, ...]:
    """amplitude, 1/wavelength, phase in turns, cos t, sin t."""
    ct, st = direction(v["angle"])
    return (v["amplitude"], 1.0 / v["wavelength"], v["phase"] / 360.0, ct, st)


SPACING = Param("spacing", "positive", "Distance between tines in canvas units, > 0.", "length")

TINE = OpDef(
    type="tine",
    help="One tine drawn along a straight line.",
    params=(POINT, ANGLE, ALPHA, LAMBDA),
    progress=(("alpha", "linear"),),
    pack=pack_tine,
    inverse=_shear(_tine_shift, -1.0),
    forward=_shear(_tine_shift, 1.0),
    example={"type": "tine", "point": [10, 35], "angle": 20, "alpha": 25, "lambda": 12},
)

COMB = OpDef(
    type="comb",
    help="A rigid comb of parallel tines, `spacing` apart.",
    params=(POINT, ANGLE, SPACING, ALPHA, LAMBDA),
    progress=(("alpha", "linear"),),
    pack=pack_tine,
    inverse=_shear(_tine_shift, -1.0, comb=True),
    forward=_shear(_tine_shift, 1.0, comb=True),
    example={
        "type": "comb",
        "point": [0, 0],
        "angle": 90,
        "spacing": 24,
        "alpha": 14,
        "lambda": 6,
    },
)

WAVE = OpDef(
    type="wave",
    help="Sinusoidal displacement along `angle`.",
    params=(
        Param("amplitude", "number", "Amplitude of the displacement in canvas units.", "amplitude"),
        Param("wavelength", "positive", "Wavelength in canvas units, > 0.", "length"),
        Param("phase", "number", "Phase in degrees.", "phase"),
        ANGLE.but(help="Direction of the displacement in degrees: 0 is +x, 90 is +y (down)."),
    ),
    progress=(("amplitude", "linear"),),
    pack=pack_wave,
    inverse=_shear(_wave_shift, -1.0),
    forward=_shear(_wave_shift, 1.0),
    example={"type": "wave", "amplitude": 6, "wavelength": 40, "phase": 30, "angle": 0},
)

OPS = (TINE, COMB, WAVE)
