"""The page's view of signals (``marblevideo live --preview``, and ``marblevideo
design`` over a live source):

- ``GET /api/signals``: ``{"t": session seconds, "values": {JSON path: y},
  "latest": {name: y}, "learning": bool, "learned": name or null, "counts":
  {...}}``: y (0..1) of each parameter of the running recipe that follows a
  signal (what its meter shows), the last value received per controller name
  (what the bind menu offers), and the state of learn.
- ``POST /api/learn``: the next controller message received (OSC or MIDI) names
  ``learned`` (MIDI learn: the page binds the slider to it).
"""

from __future__ import annotations

from marblevideo.controllers.values import ControllerSignals, SessionSignals


def signals_state(controllers: ControllerSignals, recipe, others=None, t: float = 0.0) -> dict:
    """``GET /api/signals`` for ``recipe``; ``others`` (audio) read at animation time ``t``."""
    source = SessionSignals(controllers, others)
    values = {path: source.at(track.signal, t) for path, track in recipe.signal_uses()}
    return {
        "t": round(controllers.now(), 3),
        "values": values,
        "latest": controllers.latest(),
        "learning": controllers.learning,
        "learned": controllers.learned,
        "counts": dict(controllers.counts),
    }


def learn(controllers: ControllerSignals) -> dict:
    """``POST /api/learn``."""
    controllers.learn()
    return {"learning": True}


def controllers_api(session, method: str, path: str):
    """(status, JSON object) of a live session for the routes above, or None for
    another route."""
    if (method, path) == ("GET", "/api/signals"):
        t = session.clock.now()
        return 200, signals_state(session.controllers, session.recipe, session.signals, t)
    if (method, path) == ("POST", "/api/learn"):
        return 200, learn(session.controllers)
    return None
