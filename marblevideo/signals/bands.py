"""The audio bands of the contract ("Signals"): RBJ Audio EQ Cookbook biquads.

``level`` is the mono mix as it is; ``low`` a low-pass at 150 Hz, Q = 1/sqrt 2;
``mid`` a band-pass at 1000 Hz, Q = 0.7 (constant 0 dB peak gain); ``high`` a
high-pass at 4000 Hz, Q = 1/sqrt 2. Each runs from a zero state at the stream's
first sample; :class:`FilterBank` carries the state from block to block, so a
stream filtered in blocks equals it filtered whole. float64 throughout.
SciPy is imported when a bank is made, not with this module: ``scipy.signal``
costs every command about 80 MB and a second of start-up, and only a recipe
that follows audio filters anything.
"""

from __future__ import annotations

import math

import numpy as np

#: The bands, in the order of the signal names (audio.level, ...).
BANDS = ("level", "low", "mid", "high")
#: (kind, f0 in Hz, Q) of each filtered band.
FILTERS = {
    "low": ("lowpass", 150.0, 1 / math.sqrt(2)),
    "mid": ("bandpass", 1000.0, 0.7),
    "high": ("highpass", 4000.0, 1 / math.sqrt(2)),
}


def biquad(kind: str, f0: float, q: float, sr: float) -> tuple[np.ndarray, np.ndarray]:
    """(b, a) of the cookbook's ``lowpass``, ``highpass`` or ``bandpass`` (constant
    0 dB peak gain) at ``f0`` Hz for ``sr`` samples a second, not normalised
    (a[0] = 1 + alpha; lfilter divides by it)."""
    w0 = 2 * math.pi * f0 / sr
    cos, alpha = math.cos(w0), math.sin(w0) / (2 * q)
    if kind == "lowpass":
        b = ((1 - cos) / 2, 1 - cos, (1 - cos) / 2)
    elif kind == "highpass":
        b = ((1 + cos) / 2, -(1 + cos), (1 + cos) / 2)
    elif kind == "bandpass":
        b = (alpha, 0.0, -alpha)
    else:
        raise ValueError(f"unknown biquad {kind!r}")
    return np.array(b), np.array((1 + alpha, -2 * cos, 1 - alpha))


class FilterBank:
    """Every band of one stream at ``sr`` Hz, block after block, state carried."""

    def __init__(self, sr: float):
        from scipy.signal import lfilter  # here, not at import: see the module's docstring

        self.lfilter = lfilter
        self.coefficients = {band: biquad(*spec, sr) for band, spec in FILTERS.items()}
        self.state = {band: np.zeros(2) for band in FILTERS}

    def __call__(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """The bands of the next block ``x`` (float64 mono samples)."""
        out = {"level": x}
        for band, (b, a) in self.coefficients.items():
            out[band], self.state[band] = self.lfilter(b, a, x, zi=self.state[band])
        return out
