"""Shears: ``tine``, ``comb``, ``wave``, ``rake`` and ``shift`` move a point along a
fixed direction by a shift that depends only on its coordinate across that
direction (a constant for ``shift``), so the shift computed at P' equals the
shift at P and the inverse subtracts it exactly."""

from __future__ import annotations

import math

import numpy as np

from marblevideo.limits import MAX_LIST
from marblevideo.ops.base import (
    ALPHA,
    ANGLE,
    FALLOFF,
    LAMBDA,
    POINT,
    OpDef,
    Param,
    Points,
    Values,
    direction,
)
from marblevideo.ops.gestures import Tool
from marblevideo.ops.series import SERIES_SLOTS, falloff_sum, pack_series


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


#: A line's packed floats: a point A on it, its direction M and normal N.
LINE_SLOTS = ("ax", "ay", "mx", "my", "nx", "ny")
TINE_SLOTS = (*LINE_SLOTS, "alpha_lambda", "lambda")
#: A comb's: a tine's, then the spacing s, 1/s and s/2.
COMB_SLOTS = (*TINE_SLOTS, "spacing", "inv_spacing", "half_spacing")
WAVE_SLOTS = ("amplitude", "inv_wavelength", "phase_turns", "cos", "sin")


def pack_line(v: Values) -> dict[str, float]:
    """A, M = (cos a, sin a) and N = (-sin a, cos a)."""
    ca, sa = direction(v["angle"])
    (ax, ay) = v["point"]
    return {"ax": ax, "ay": ay, "mx": ca, "my": sa, "nx": -sa, "ny": ca}


def pack_tine(v: Values, lists: list) -> dict[str, float]:
    """The line, alpha lambda, lambda; for a comb then spacing, 1/spacing, spacing/2."""
    row = {**pack_line(v), "alpha_lambda": v["alpha"] * v["lambda"], "lambda": v["lambda"]}
    if "spacing" in v:
        s = v["spacing"]
        row.update(spacing=s, inv_spacing=1.0 / s, half_spacing=s / 2.0)
    return row


def pack_wave(v: Values, lists: list) -> dict[str, float]:
    """amplitude, 1/wavelength, phase in turns, cos t, sin t."""
    ct, st = direction(v["angle"])
    inv_w, turns = 1.0 / v["wavelength"], v["phase"] / 360.0
    return {
        "amplitude": v["amplitude"],
        "inv_wavelength": inv_w,
        "phase_turns": turns,
        "cos": ct,
        "sin": st,
    }


SPACING = Param("spacing", "positive", "Distance between tines in canvas units, > 0.", "length")

TINE = OpDef(
    type="tine",
    help="One tine drawn along a straight line.",
    params=(POINT, ANGLE, ALPHA, LAMBDA),
    progress=(("alpha", "linear"),),
    slots=TINE_SLOTS,
    pack=pack_tine,
    inverse=_shear(_tine_shift, -1.0),
    forward=_shear(_tine_shift, 1.0),
    tools=(
        Tool(
            "line",
            {
                "point": "a",
                "angle": "angle",
                "alpha": {"positive": "len"},
                "lambda": {"positive": {"div": ["side", 25]}},
            },
            label="alpha",
        ),
    ),
    example={"type": "tine", "point": [10, 35], "angle": 20, "alpha": 25, "lambda": 12},
)

COMB = OpDef(
    type="comb",
    help="A rigid comb of parallel tines, `spacing` apart.",
    params=(POINT, ANGLE, SPACING, ALPHA, LAMBDA),
    progress=(("alpha", "linear"),),
    slots=COMB_SLOTS,
    pack=pack_tine,
    inverse=_shear(_tine_shift, -1.0, comb=True),
    forward=_shear(_tine_shift, 1.0, comb=True),
    # it moves the whole sheet (by alpha at its tines): a tenth of the drag, at most its spacing
    tools=(
        Tool(
            "line",
            {
                "point": "a",
                "angle": "angle",
                "spacing": {"positive": {"div": ["side", 16]}},
                "alpha": {"positive": {"min": [{"div": ["len", 10]}, "op.spacing"]}},
                "lambda": {"positive": {"div": ["side", 60]}},
            },
            label="alpha",
        ),
    ),
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
    slots=WAVE_SLOTS,
    pack=pack_wave,
    inverse=_shear(_wave_shift, -1.0),
    forward=_shear(_wave_shift, 1.0),
    tools=(
        Tool(
            "line",
            {
                "amplitude": {"positive": {"div": ["side", 30]}},
                "wavelength": {"positive": "len"},
                "phase": 0,
                "angle": "angle",
            },
            label="wavelength",
        ),
    ),
    example={"type": "wave", "amplitude": 6, "wavelength": 40, "phase": 30, "angle": 0},
)


def _offset(sign: float):
    def move(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
        dx, dy = v["offset"]
        return x + sign * dx, y + sign * dy

    return move


SHIFT = OpDef(
    type="shift",
    help="The whole tank moved by `offset`.",
    params=(Param("offset", "point", "The motion [dx, dy] in canvas units.", handle=False),),
    progress=(("offset", "linear"),),
    slots=("dx", "dy"),
    pack=lambda v, lists: dict(zip(("dx", "dy"), v["offset"], strict=True)),
    inverse=_offset(-1.0),
    forward=_offset(1.0),
    tools=(Tool("line", {"offset": {"round1": ["dx", "dy"]}}, label="offset"),),
    example={"type": "shift", "offset": [9, -6]},
)


def rake_offsets(v: Values) -> list[float]:
    """A rake's tine offsets along N from its point: ``tines``, else ``count``
    tines ``spacing`` apart, centred on the point."""
    if "tines" in v:
        return [float(o) for o in v["tines"]]
    n, s = int(v["count"]), float(v["spacing"])
    return [(k - (n - 1) / 2) * s for k in range(n)]


def _rake_shift(v: Values, x: np.ndarray, y: np.ndarray, comb: bool = False):
    """Shift along M: alpha * sum_i exp(-|d_i| / falloff), d_i = (P - A) . N - o_i
    (evenly spaced tines summed in closed form: :func:`~marblevideo.ops.series.falloff_sum`)."""
    mx, my = direction(v["angle"])
    ax, ay = v["point"]
    across = (x - ax) * -my + (y - ay) * mx  # (P - A) . N
    return v["alpha"] * falloff_sum(across, rake_offsets(v), v["falloff"]), mx, my


#: A rake's packed floats: the line, alpha, 1/falloff, then its tines as a series.
RAKE_SLOTS = (*LINE_SLOTS, "alpha", "inv_falloff", *SERIES_SLOTS)


def pack_rake(v: Values, lists: list) -> dict[str, float]:
    """The line, alpha, 1/falloff, and its tines as a series (where their data
    start in ``lists``, how many, whether in closed form: :mod:`marblevideo.ops.series`)."""
    offsets = rake_offsets(v)
    series = pack_series(offsets, [1.0] * len(offsets), v["falloff"], lists)
    return {**pack_line(v), "alpha": v["alpha"], "inv_falloff": 1.0 / v["falloff"], **series}


def check_rake(op, tracks) -> list:
    """``tines``, or ``spacing`` with ``count`` (at most MAX_LIST tines)."""
    given = [name for name in ("tines", "spacing", "count") if name in op]
    if "tines" in op and len(given) > 1:
        return [([given[1]], "give the tines as `tines` or as `spacing` and `count`, not both")]
    if "tines" not in op and len(given) < 2:
        missing = "missing 'count'" if given == ["spacing"] else "missing 'spacing'"
        if not given:
            return [([], "missing 'tines' (or 'spacing' and 'count')")]
        return [([given[0]], f"{missing}: a rake's tines are `tines` or `spacing` and `count`")]
    if op.get("count", 0) > MAX_LIST:
        return [(["count"], f"must be <= {MAX_LIST} (tines of one rake), got {op['count']}")]
    return []


RAKE = OpDef(
    type="rake",
    help="Several tines drawn at once along `angle`, each pulling with an exponential fall-off.",
    params=(
        POINT.but(help="A point [x, y] the tines' offsets are measured from (canvas units)."),
        ANGLE.but(help="Direction of the motion in degrees: 0 is +x, 90 is +y (down)."),
        ALPHA.but(help="Shift at a tine in canvas units; negative reverses the motion."),
        FALLOFF,
        Param(
            "tines",
            "numberList",
            "Offsets of the tines from `point` across the motion (canvas units).",
            optional=True,
        ),
        SPACING.but(
            help="Distance between tines (with `count`, instead of `tines`).", optional=True
        ),
        Param(
            "count", "count", "Number of tines, centred on `point` (with `spacing`).", optional=True
        ),
    ),
    progress=(("alpha", "linear"),),
    slots=RAKE_SLOTS,
    pack=pack_rake,
    inverse=_shear(_rake_shift, -1.0),
    forward=_shear(_rake_shift, 1.0),
    check=check_rake,
    tools=(
        Tool(
            "line",
            {
                "point": "a",
                "angle": "angle",
                "alpha": {"positive": "len"},
                "falloff": {"positive": {"div": ["side", 60]}},
                "spacing": {"positive": {"div": ["side", 12]}},
                "count": 9,
            },
            label="alpha",
        ),
    ),
    example={
        "type": "rake",
        "point": [40, 30],
        "angle": 0,
        "alpha": 7,
        "falloff": 4,
        "spacing": 12,
        "count": 5,
    },
)

OPS = (TINE, COMB, WAVE, SHIFT, RAKE)
