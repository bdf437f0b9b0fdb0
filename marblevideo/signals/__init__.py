"""Signals' sources (docs/recipe-format.md, "Signals"): the audio analysis
(:mod:`~marblevideo.signals.audio`: bands, 100 Hz levels, envelopes) and the
values a render reads (:mod:`~marblevideo.signals.values`). The recipe side,
names and :class:`~marblevideo.recipe.signals.SignalTrack`, is in
:mod:`marblevideo.recipe.signals`."""

from marblevideo.signals.audio import Analysis, analyse
from marblevideo.signals.values import AudioSignals, Sources

__all__ = ["Analysis", "AudioSignals", "Sources", "analyse"]
