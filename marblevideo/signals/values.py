"""Signal values from an audio analysis (:class:`AudioSignals`) and several
sources behind one :class:`~marblevideo.recipe.signals.SignalValues`
(:class:`Sources`): a live session adds its controllers beside the audio.

Time t is seconds from the first frame; y = e_i with i = floor(100 t + 1e-9),
e the envelope of the dB-mapped levels (:mod:`marblevideo.signals.levels`).
"""

from __future__ import annotations

import math

from marblevideo.recipe.signals import Signal, SignalValues
from marblevideo.signals.audio import Analysis
from marblevideo.signals.levels import RATE, db_map, envelope, held


class AudioSignals:
    """The audio signals of one :class:`~marblevideo.signals.audio.Analysis`; the
    envelope of each distinct signal (band, db, attack, release) is made once."""

    def __init__(self, analysis: Analysis):
        self.analysis = analysis
        self._envelopes: dict[Signal, object] = {}

    def envelope(self, signal: Signal):
        """e_i of ``signal`` for i = 0 .. the end of the analysis."""
        key = Signal(signal.name, signal.db, signal.attack, signal.release)
        if key not in self._envelopes:
            v = db_map(self.analysis.rms[signal.band], signal.db)
            self._envelopes[key] = envelope(v, signal.attack, signal.release)
        return self._envelopes[key]

    def at(self, signal: Signal, t: float) -> float:
        """y of an audio ``signal`` at ``t`` seconds."""
        if signal.controller:
            raise ValueError(f"{signal.name}: not an audio signal")
        i = math.floor(RATE * t + 1e-9)
        if i < 0:
            return 0.0
        e = self.envelope(signal)
        if i < len(e):
            return float(e[i])
        silent = float(db_map(0.0, signal.db))  # windows of no sample: r = 0
        last = float(e[-1]) if len(e) else 0.0
        return held(last, silent, i - len(e) + 1, signal.attack, signal.release)


class Sources:
    """Several sources as one: each signal asks the source of its kind
    (``audio``, ``osc``, ``midi``)."""

    def __init__(self, **sources: SignalValues):
        self.sources = sources

    def at(self, signal: Signal, t: float) -> float:
        return self.sources[signal.source].at(signal, t)
