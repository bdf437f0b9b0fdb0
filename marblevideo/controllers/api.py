"""The live page's view of signals (``marblevideo live --preview``):

- ``GET /api/signals``: ``{"t": session seconds, "values": {JSON path: y},
  "latest": {name: y}, "learning": bool, "learned": name or null, "counts":
  {...}}``: y (0..1) of each parameter of the running recipe that follows a
  signal (what its meter shows), the last value received per controller name
  (what the bind menu offers), and the state of learn.
- ``POST /api/learn``: the next controller message received (OSC or MIDI) names
  ``learned`` (MIDI learn: the page binds the slider to it).
"""

from __future__ import annotations

from marblevideo.controllers.values import SessionSignals


def signals_state(session) -> dict:
    controllers = session.controllers
    source = SessionSignals(controllers, session.signals)  # audio: at the animation clock's t
    t = session.clock.now()
    values = {path: source.at(track.signal, t) for path, track in session.recipe.signal_uses()}
    return {
        "t": round(controllers.now(), 3),
        "values": values,
        "latest": controllers.latest(),
        "learning": controllers.learning,
        "learned": controllers.learned,
        "counts": dict(controllers.counts),
    }


def controllers_api(session, method: str, path: str):
    """(status, JSON object) for the routes above, or None for another route."""
    if (method, path) == ("GET", "/api/signals"):
        return 200, signals_state(session)
    if (method, path) == ("POST", "/api/learn"):
        session.controllers.learn()
        return 200, {"learning": True}
    return None
