"""``jiggle``: the tank shaken back and forth (not area preserving: a transfer
effect). Along M each point moves by A sin(tau), across by B cos(tau), where
tau = k (P . M) + f and k = 2 pi / wavelength.

The inverse solves s + A sin(k s + f) = s' for s = P . M, which has one
solution while |k A| < 1: the recipe is refused (exit 2) where a key breaks
that, and between keys A is held to 0.99 / k (:func:`settle`). The NumPy
inverse is Newton's method kept inside the bracket s' - |A| .. s' + |A|, to
1e-12 canvas units; the kernel does the same in float32.
"""

from __future__ import annotations

import math

import numpy as np

from marblevideo.ops.base import ANGLE, OpDef, Param, Points, Values, direction
from marblevideo.ops.gestures import Tool

#: Largest |k A| a frame renders with (keys must stay below 1).
KA_LIMIT = 0.99


def _terms(v: Values):
    mx, my = direction(v["angle"])
    k = 2 * math.pi / v["wavelength"]
    return mx, my, k, math.radians(v["phase"]), v["major"], v["minor"]


def forward(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
    """P' = P + A sin(tau) M + B cos(tau) N, tau = k (P . M) + f."""
    mx, my, k, f, a, b = _terms(v)
    tau = k * (x * mx + y * my) + f
    along, across = a * np.sin(tau), b * np.cos(tau)
    return x + along * mx - across * my, y + along * my + across * mx


def solve_along(v: Values, s_out: np.ndarray, tol: float = 1e-12) -> np.ndarray:
    """s with s + A sin(k s + f) = s_out: safeguarded Newton in float64."""
    _, _, k, f, a, _ = _terms(v)
    s = np.array(s_out, dtype=np.float64, copy=True)
    lo, hi = s - abs(a), s + abs(a)
    for _ in range(200):
        g = s + a * np.sin(k * s + f) - s_out
        lo, hi = np.where(g < 0, s, lo), np.where(g > 0, s, hi)
        step = g / (1 + a * k * np.cos(k * s + f))
        nxt = s - step
        outside = (nxt <= lo) | (nxt >= hi)
        nxt = np.where(outside, 0.5 * (lo + hi), nxt)
        done = np.all(np.abs(nxt - s) <= tol * np.maximum(1.0, np.abs(s_out)))
        s = nxt
        if done:
            break
    return s


def inverse(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
    """P = P' - A sin(tau) M - B cos(tau) N with tau = k s + f, s solving the above."""
    mx, my, k, f, a, b = _terms(v)
    s = solve_along(v, x * mx + y * my)
    tau = k * s + f
    along, across = a * np.sin(tau), b * np.cos(tau)
    return x - along * mx + across * my, y - along * my - across * mx


#: A jiggle's packed floats: M, 1/wavelength, the phase in turns, A, B, k A (the
#: derivative's term), then what float32 loses of the first four (``_lo``; the
#: kernel adds them back in float64).
EXACT_SLOTS = ("mx", "my", "inv_wavelength", "phase_turns")
SLOTS = (*EXACT_SLOTS, "major", "minor", "ka", *(f"{name}_lo" for name in EXACT_SLOTS))


def pack(v: Values, lists: list) -> dict[str, float]:
    """:data:`SLOTS`: each exact value as its float32 part and the rest."""
    mx, my, k, _, a, b = _terms(v)
    exact = (mx, my, 1.0 / v["wavelength"], (v["phase"] / 360.0) % 1.0)
    row = {"major": a, "minor": b, "ka": k * a}
    for name, value in zip(EXACT_SLOTS, exact, strict=True):
        row[name] = high = float(np.float32(value))
        row[f"{name}_lo"] = value - high
    return row


def check(op, tracks) -> list:
    """|2 pi major / wavelength| < 1 at every key of either (one inverse)."""
    major, wavelength = tracks["major"], tracks["wavelength"]
    times = sorted({0.0, *major.key_times, *wavelength.key_times})
    for t in times:
        ka = 2 * math.pi * abs(major.at(t)) / wavelength.at(t)
        if ka >= 1:
            # the key at t, if either track has one (t = 0 may be before both's first)
            name = (
                "wavelength" if t in wavelength.key_times and t not in major.key_times else "major"
            )
            track = major if name == "major" else wavelength
            path = [name]
            if track.keyed and t in track.key_times:
                path += ["keys", track.key_times.index(t), "v"]
            return [
                (
                    path,
                    f"|2 pi major / wavelength| must be < 1 (else the shake has no single "
                    f"inverse), got {ka:.3g} at t={t:g}",
                )
            ]
    return []


def settle(values: dict) -> dict:
    """A held to KA_LIMIT / k where a frame between keys asks for more."""
    limit = KA_LIMIT * values["wavelength"] / (2 * math.pi)
    values["major"] = max(-limit, min(limit, values["major"]))
    return values


JIGGLE = OpDef(
    type="jiggle",
    help="The tank shaken back and forth: a transfer effect, not area preserving.",
    params=(
        ANGLE.but(help="Direction M of the shake in degrees: 0 is +x, 90 is +y (down)."),
        Param("wavelength", "positive", "Wavelength in canvas units, > 0.", "length"),
        Param("phase", "number", "Phase in degrees.", "phase"),
        Param(
            "major",
            "number",
            "Amplitude A along the shake (canvas units); |2 pi A / wavelength| < 1.",
            "amplitude",
        ),
        Param("minor", "number", "Amplitude B across the shake (canvas units).", "amplitude"),
    ),
    progress=(("major", "linear"), ("minor", "linear")),
    slots=SLOTS,
    pack=pack,
    inverse=inverse,
    forward=forward,
    check=check,
    settle=settle,
    tools=(
        Tool(
            "line",
            {
                "angle": "angle",
                "wavelength": {"positive": "len"},
                "phase": 0,
                "major": {"round1": {"div": ["op.wavelength", 10]}},
                "minor": {"round1": {"div": ["op.wavelength", 20]}},
            },
            label="wavelength",
        ),
    ),
    example={
        "type": "jiggle",
        "angle": 30,
        "wavelength": 30,
        "phase": 20,
        "major": 3,
        "minor": 2,
    },
)

OPS = (JIGGLE,)
