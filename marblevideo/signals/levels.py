"""Levels on the contract's 100 Hz grid, the dB map and the envelope.

Sample j of a stream at ``sr`` Hz lies at time a0 + j / sr (seconds from the
first video frame). r_i, the RMS of a band's samples in [i/100 - 0.05, i/100),
is built from 10 ms slots: slot k holds the samples in [k/100, (k+1)/100), so
window i is slots i-5 .. i-1. :class:`Slots` sums each slot's squares as the
stream goes by, block after block (slot boundaries in exact rational arithmetic,
so no sample lands in the wrong slot), keeping 4 floats a slot, never samples.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

#: Grid steps a second, and slots a window.
RATE = 100
WINDOW = 5
#: The RMS below which a level is floored (-200 dB).
FLOOR = 1e-10


class Slots:
    """Sums of squares and counts of samples per 10 ms slot, from slot -WINDOW on
    (earlier slots feed no window of t >= 0)."""

    def __init__(self, sr: int, a0: Fraction, bands: tuple[str, ...]):
        self.sr, self.a0, self.bands = sr, Fraction(a0), bands
        self.j = 0  # index of the next sample
        self.sums: dict[str, list[np.ndarray]] = {band: [] for band in bands}
        self.counts: list[np.ndarray] = []
        self.next_slot = -WINDOW  # the first slot not yet stored

    def slot(self, j: int) -> int:
        """The slot of sample j: floor(100 (a0 + j / sr))."""
        return math.floor((self.a0 + Fraction(j, self.sr)) * RATE)

    def first(self, k: int) -> int:
        """The first sample of slot k: ceil((k / 100 - a0) sr)."""
        return math.ceil((Fraction(k, RATE) - self.a0) * self.sr)

    def add(self, blocks: dict[str, np.ndarray]) -> None:
        """The next samples of every band (arrays of one length)."""
        n = len(next(iter(blocks.values())))
        j0 = self.j
        self.j += n
        if n == 0:
            return
        k0, k1 = self.slot(j0), self.slot(j0 + n - 1)
        lo = max(k0, -WINDOW)
        if k1 < lo:
            return
        cuts = np.array([max(self.first(k), j0) - j0 for k in range(lo, k1 + 1)])
        counts = np.diff(np.append(cuts, n))
        for band in self.bands:
            sums = np.add.reduceat(np.square(blocks[band]), cuts)
            sums[counts == 0] = 0.0  # reduceat gives x[cut] for an empty slot
            self._store(self.sums[band], sums, lo)
        self._store(self.counts, counts, lo)
        self.next_slot = k1 + 1

    def _store(self, parts: list[np.ndarray], values: np.ndarray, lo: int) -> None:
        """Append slots lo .. to ``parts`` (the first may continue the last stored)."""
        if lo < self.next_slot:
            parts[-1][-1] += values[0]
            values = values[1:]
        elif lo > self.next_slot:
            parts.append(np.zeros(lo - self.next_slot, values.dtype))
        if len(values):
            parts.append(values.copy())

    def rms(self) -> dict[str, np.ndarray]:
        """r_i for i = 0 .. the last window holding a sample, per band (0 for
        windows of no sample)."""
        n = _windows(_joined(self.counts, np.int64))
        out = {}
        for band in self.bands:
            total = _windows(_joined(self.sums[band], np.float64))
            out[band] = np.sqrt(total / np.maximum(n, 1)) * (n > 0)
        return out


def _joined(parts: list[np.ndarray], dtype) -> np.ndarray:
    return np.concatenate(parts).astype(dtype) if parts else np.zeros(0, dtype)


def _windows(slots: np.ndarray) -> np.ndarray:
    """Window i = slots i-5 .. i-1, stored from slot -5 on (index s is slot s - 5),
    so window i sums indices i .. i+4; for i = 0 .. the last stored index."""
    padded = np.concatenate([slots, np.zeros(WINDOW - 1, slots.dtype)])
    return sum(padded[shift : shift + len(slots)] for shift in range(WINDOW))


def db_map(r: np.ndarray | float, db: tuple[float, float]) -> np.ndarray:
    """v = clamp((20 log10(max(r, 1e-10)) - d0) / (d1 - d0), 0, 1)."""
    d0, d1 = db
    level = 20 * np.log10(np.maximum(r, FLOOR))
    return np.clip((level - d0) / (d1 - d0), 0.0, 1.0)


def coefficient(tau: float) -> float:
    """c = 1 - exp(-0.01 / tau); 1 for tau = 0."""
    return 1.0 if tau == 0 else -math.expm1(-1.0 / (RATE * tau))


def envelope(v: np.ndarray, attack: float, release: float) -> np.ndarray:
    """e_i = e_{i-1} + c (v_i - e_{i-1}) from e_{-1} = 0, c by ``attack`` where
    v_i > e_{i-1}, else by ``release``."""
    up, down = coefficient(attack), coefficient(release)
    if up == down == 1.0:
        return np.asarray(v, dtype=np.float64).copy()
    out = np.empty(len(v))
    e = 0.0
    for i, x in enumerate(np.asarray(v, dtype=np.float64).tolist()):
        e += (up if x > e else down) * (x - e)
        out[i] = e
    return out


def held(last: float, v: float, steps: int, attack: float, release: float) -> float:
    """The envelope ``steps`` grid steps after ``last`` when v stays at ``v``
    (it approaches v from one side, so one coefficient applies throughout)."""
    c = coefficient(attack if v > last else release)
    return v + (last - v) * (1.0 - c) ** steps
