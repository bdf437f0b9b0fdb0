"""Signals' sources (docs/recipe-format.md, "Signals"): the audio analysis
(:mod:`~marblevideo.signals.audio`: bands, 100 Hz levels, envelopes) and the
values a render reads (:mod:`~marblevideo.signals.values`). The recipe side,
names and :class:`~marblevideo.recipe.signals.SignalTrack`, is in
:mod:`marblevideo.recipe.signals`. The names below are imported on first use
(:mod:`marblevideo.lazy`): PyAV comes with a recipe that follows audio only."""

from __future__ import annotations

from typing import TYPE_CHECKING

from marblevideo.lazy import lazy_names

if TYPE_CHECKING:
    from marblevideo.signals.audio import Analysis, analyse
    from marblevideo.signals.values import AudioSignals, Sources

__all__ = ["Analysis", "AudioSignals", "Sources", "analyse"]
_MODULES = {"Analysis": "audio", "analyse": "audio", "AudioSignals": "values", "Sources": "values"}
__getattr__ = lazy_names(__name__, {k: f"{__name__}.{m}" for k, m in _MODULES.items()})
