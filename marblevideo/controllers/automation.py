"""A live session's take as keyframes (``marblevideo live ... --automation FILE``).

The recipe as it is when the session ends, with each controller signal
``{"signal": NAME, "range": [lo, hi], ...}`` replaced by the keyframe track of
what it did over the whole session: a key at t = i / 100 (seconds from the
session's start, the 100 Hz grid of
:mod:`~marblevideo.controllers.values`) wherever lo + (hi - lo) e_i changes
(to 1e-9), each leaving with ease ``hold``; so the track at t is the value the
session showed at t, one key for a held value, at most 100 keys a second.
Rendering FILE over the same source replays the take.
"""

from __future__ import annotations

import copy
import json
import os

from marblevideo.controllers.values import ControllerSignals, step
from marblevideo.media.output import atomic_output
from marblevideo.recipe.signals import signal_track

#: Decimals kept of a recorded value (changes below this are no change).
DECIMALS = 9


def recorded_track(value: dict, signals: ControllerSignals, end: float) -> dict:
    """The keyframe track of the signal object ``value`` over 0 .. ``end`` seconds."""
    track = signal_track(value)
    e = signals.envelope(track.signal, step(end) + 1)
    keys: list[dict] = []
    for i, y in enumerate(e.tolist()):
        v = round(track.lo + (track.hi - track.lo) * y, DECIMALS)
        if not keys or v != keys[-1]["v"]:
            if keys:
                keys[-1]["ease"] = "hold"
            keys.append({"t": round(i / 100, 2), "v": v})
    return {"keys": keys}


def recorded(doc, signals: ControllerSignals, end: float):
    """``doc`` (a recipe's JSON) with every controller signal replaced by its track."""
    if isinstance(doc, dict):
        if isinstance(doc.get("signal"), str) and not doc["signal"].startswith("audio."):
            return recorded_track(doc, signals, end)
        return {k: recorded(v, signals, end) for k, v in doc.items()}
    if isinstance(doc, list):
        return [recorded(v, signals, end) for v in doc]
    return copy.copy(doc)


def write_automation(
    path: str | os.PathLike, doc, signals: ControllerSignals, end: float, overwrite: bool
) -> dict:
    """Write the take to ``path`` atomically (a temporary file beside it, renamed);
    the document written."""
    out = recorded(doc, signals, end)
    with atomic_output(path, overwrite=overwrite) as tmp:
        tmp.write_text(json.dumps(out, indent=2) + "\n", encoding="utf-8")
    return out
