"""Sums of exponential fall-offs, sum_k c_k e^(-|u - o_k| / L): a rake's tines
(u across the motion, c_k = 1) and a stir's rings (u the radius, c_k the
rings' signs), packed for the kernel's ``series_sum`` (kernels/math.cl).

Evenly spaced positions whose coefficients are all equal or alternate in sign
are summed in closed form there: two geometric series either side of u, four
exponentials for any n (the same sum; float32 agrees with the float64 sum of
every term). Closer positions than ``MIN_RATIO`` falloffs apart lose float32
precision in the series, and fewer than ``SERIES_MIN`` gain nothing: those,
and uneven ones, are summed term by term.
"""

from __future__ import annotations

import math

import numpy as np

#: Fewest terms summed in closed form.
SERIES_MIN = 4
#: Smallest spacing / falloff summed in closed form.
MIN_RATIO = 0.05


#: A series' packed floats (an op's last slots): where its data start in
#: ``lists``, how many terms, 1.0 when in closed form else 0.0.
SERIES_SLOTS = ("series_at", "series_n", "series_even")


def pack_series(
    positions: list[float], coefficients: list[float], falloff: float, lists: list
) -> dict[str, float]:
    """Append the sum's data to ``lists``; its :data:`SERIES_SLOTS`. Closed form:
    o0, 1/s, s, s/L, 1/(1 - sigma q), c0, sigma, sigma^(n-1), with q = e^(-s/L),
    for o_k = o0 + k s (sorted) and c_k = c0 sigma^k; term by term: the n
    positions, then the n coefficients."""
    at, n = len(lists), len(positions)
    closed = _closed_form(positions, coefficients, falloff) if n >= SERIES_MIN else None
    if closed is not None:
        lists.extend(closed)
        return {"series_at": at, "series_n": n, "series_even": 1.0}
    lists.extend(float(o) for o in positions)
    lists.extend(float(c) for c in coefficients)
    return {"series_at": at, "series_n": n, "series_even": 0.0}


def _even_step(o: list[float]) -> float | None:
    """The spacing of sorted positions ``o`` if they are evenly spaced, else None."""
    n = len(o)
    step = (o[-1] - o[0]) / (n - 1)
    if step <= 0 or any(abs(o[k] - (o[0] + k * step)) > 1e-9 * step for k in range(n)):
        return None
    return step


def falloff_sum(u: np.ndarray, positions: list[float], falloff: float) -> np.ndarray:
    """sum_k e^(-|u - o_k| / L) in float64 (all coefficients 1: a rake's tines).

    Evenly spaced positions (at least :data:`SERIES_MIN`, at least
    :data:`MIN_RATIO` falloffs apart) are summed in closed form: with j the
    positions at or below u and q = e^(-s/L), the j below give
    e^(-(u - o_(j-1))/L) (1 - q^j) / (1 - q) and the n - j above
    e^(-(o_j - u)/L) (1 - q^(n-j)) / (1 - q); the same sum to rounding, for any
    n in the time of four exponentials. Others are summed term by term.
    """
    u = np.asarray(u, np.float64)
    o = sorted(float(p) for p in positions)
    n = len(o)
    step = _even_step(o) if n >= SERIES_MIN else None
    if step is None or step / falloff < MIN_RATIO:
        total = np.zeros(u.shape)
        for p in o:  # one term at a time: memory stays that of u
            total += np.exp(-np.abs(u - p) / falloff)
        return total
    ratio = step / falloff
    j = np.clip(np.floor((u - o[0]) / step) + 1.0, 0.0, n)
    # distances to the nearest position below and above u; where there is none
    # its count is 0 and the distance is only kept finite
    below = np.maximum(u - (o[0] + (j - 1.0) * step), -step)
    above = np.maximum(o[0] + j * step - u, -step)
    total = np.exp(-below / falloff) * -np.expm1(-j * ratio)
    total += np.exp(-above / falloff) * -np.expm1(-(n - j) * ratio)
    return total / -math.expm1(-ratio)


def _closed_form(positions, coefficients, falloff: float) -> tuple[float, ...] | None:
    pairs = sorted(zip(positions, coefficients, strict=True))
    o, c = [p[0] for p in pairs], [p[1] for p in pairs]
    n = len(o)
    step = _even_step(o)
    if step is None:
        return None
    ratio = step / falloff
    if ratio < MIN_RATIO:
        return None
    if all(ck == c[0] for ck in c):
        sigma = 1.0
    elif all(ck == c[0] * (-1) ** k for k, ck in enumerate(c)):
        sigma = -1.0
    else:
        return None
    g = 1.0 / -math.expm1(-ratio) if sigma > 0 else 1.0 / (1.0 + math.exp(-ratio))
    return (o[0], 1.0 / step, step, ratio, g, c[0], sigma, sigma ** (n - 1))
