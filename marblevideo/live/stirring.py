"""A live session's motion (the recipe's ``motion``, revision 4): each frame rendered
is seen by one :class:`~marblevideo.motion.StirredRecipe`, and the recipe it
returns (the recipe's ops, then the motion strokes on top) is what renders.

- Time: the tracker sees a frame at its *frame time*: a file's frames at their
  time in the file (a looped file goes on after its end, one frame period after
  its last frame, so the tracker's time never goes back), other sources' at their
  capture time from the session's start. A file's frames are seen as their
  decoded luma plane, as a file render sees them (a camera's as the RGBA's
  luma). A file played live and rendered as a file thus give the tracker the
  same frames at the same times, as long as the live session drops none (a
  slow session drops frames, and the tracker sees fewer; its strokes then
  differ from the file render's). The frame is rendered at the animation
  clock's time, as without motion: the two agree (within :data:`SHIFT`) while
  the clock plays from the session's start; when the clock is paused, scrubbed
  or looped, the motion strokes are moved in time to it, so they show as the
  frames made them while the recipe's own ops follow the clock (the take keeps
  them in the frames' time).
- Edits: a new recipe keeps the tracker (its strokes, the regions it follows);
  the new recipe's ``motion`` fields apply from the next frame (a stroke keeps
  the gain, memory and heal it was made with; the strokes made after take the
  new ones). A recipe without ``motion`` renders without motion strokes and the
  tracker waits (it sees no frame); when ``motion`` comes back, it goes on.
- The state the page shows (``GET /api/motion``: :meth:`LiveMotion.state`) is
  read under the same lock as the frames are seen.
"""

from __future__ import annotations

import dataclasses
import threading

import numpy as np

#: Seconds between a frame's time and the animation clock's beyond which the
#: motion strokes are moved to the clock (it is paused, scrubbed or looped).
SHIFT = 0.5


class LiveMotion:
    """The motion of one live session (idle until its recipe has ``motion``)."""

    def __init__(self, fps: float):
        self.period = 1.0 / fps if fps > 0 else 0.0
        self._lock = threading.Lock()
        self._stirred = None  # marblevideo.motion.StirredRecipe, made at the first frame
        self._given = None  # the recipe it was last given
        self._marbler = None  # the Marbler of the last recipe with motion strokes
        self._bound = (None, None)  # (the last stirred recipe, it with the signals bound)
        self.active = False  # the last frame's recipe had motion
        self.t: float | None = None  # the last frame's time
        self.frames = 0  # frames seen
        # a looped file: the time added to its times in the pass under way
        self._offset = 0.0
        self._last_media: float | None = None

    def frame_time(self, media_t: float | None, ts: float, started: float) -> float:
        """The time the tracker sees a frame at: ``media_t`` (a file's, continued
        across loops), else ``ts - started`` (capture time from the session's start)."""
        if media_t is None:
            return ts - started
        if self._last_media is not None and media_t < self._last_media:  # a new pass
            self._offset += self._last_media + self.period
        self._last_media = media_t
        return self._offset + media_t

    def see(self, recipe, frame: np.ndarray, t: float):
        """The recipe to render ``frame`` (RGBA, or its luma plane) of time ``t``
        with: ``recipe`` itself when it has no ``motion``, else its ops and the
        motion strokes."""
        if recipe.motion is None:
            self.active = False
            return recipe
        with self._lock:
            if recipe is not self._given:
                size = (frame.shape[1], frame.shape[0])
                self._stirred = _continued(self._stirred, recipe, size)
            self._given = recipe
            self.active, self.t = True, t
            self.frames += 1
            stirred = self._stirred.see(frame, t)
        if recipe.signals is None:
            return stirred
        if self._bound[0] is not stirred:  # the same object while the strokes do not change
            self._bound = (stirred, stirred.bind(recipe.signals))
        return self._bound[1]

    def marbler(self, marbler, frame: np.ndarray, t: float, shown: float | None = None):
        """``marbler``, or with ``motion`` one of the same renderer for the recipe
        with the motion strokes that ``frame`` of time ``t`` leaves (kept while the
        strokes do not change; the loop walk's one program renders any ops).
        ``shown``: the animation clock's time the frame is rendered at; more than
        :data:`SHIFT` s from ``t`` (paused, scrubbed, looped), the strokes are moved
        by the difference in time, so they show as the frames made them."""
        recipe = self.see(marbler.recipe, frame, t)
        if recipe is marbler.recipe:
            return marbler
        if shown is not None and abs(shown - t) > SHIFT:
            recipe = self._shifted(marbler.recipe, shown - t)
        if self._marbler is None or self._marbler.recipe is not recipe:
            self._marbler = marbler.with_recipe(recipe)
        return self._marbler

    def over(self, base, shown: float):
        """``base`` (any recipe: the designer's, :mod:`marblevideo.design.motion`)
        with the motion strokes of the last frame seen, moved in time by ``shown``
        minus that frame's time, so that rendered at ``shown`` they show as that
        frame left them; ``base`` itself when it has no ``motion`` or no frame was
        seen with motion (the last frame's recipe had none)."""
        with self._lock:
            if base.motion is None or self._stirred is None or not self.active:
                return base
            strokes, shift = self._stirred.tracker.strokes(), shown - self.t
        return _with_strokes(base, strokes, shift)

    def _shifted(self, base, shift: float):
        """``base`` (the recipe without motion strokes) with the motion strokes of
        now, their ``times`` and ``heal`` moved by ``shift`` seconds."""
        with self._lock:
            strokes = self._stirred.tracker.strokes()
        return _with_strokes(base, strokes, shift)

    def state(self, shapes: bool = True) -> dict:
        """``GET /api/motion``: whether the recipe has motion (``active``), the last
        frame's ``t``, ``level`` (0..1), the ``regions`` followed ({center, radius,
        speed, stroke}: canvas units, units per second, the index of its stroke in
        the take or None) and the ``strokes`` rendered now (stroke ops); both lists
        empty unless ``shapes`` (the page's meter needs only the level)."""
        with self._lock:
            tracker = None if self._stirred is None else self._stirred.tracker
            if tracker is None:
                return {"active": False, "t": None, "level": 0.0, "regions": [], "strokes": []}
            return {
                "active": self.active,
                "t": self.t,
                "frames": self.frames,
                "level": float(tracker.level()),
                "regions": _plain(tracker.regions()) if shapes else [],
                "strokes": _plain(tracker.strokes()) if shapes else [],
            }

    def take_document(self, document: dict) -> dict:
        """``--automation``: ``document`` with every motion stroke made as ordinary
        ``stroke`` ops after its own, and without ``motion`` (as it is when no
        stroke was ever made and the recipe has no motion)."""
        with self._lock:
            if self._stirred is None:
                return {k: v for k, v in document.items() if k != "motion"}
            return self._stirred.take_document(document)


def _with_strokes(base, strokes: list[dict], shift: float):
    """``base`` without ``motion``, its ops followed by the stroke ops ``strokes``
    (the tracker's) moved ``shift`` seconds later."""
    from marblevideo.recipe.load import build_op

    n, entries = len(base.ops), base.entries
    ops = [build_op(_moved(op, shift), n + k, entries + k) for k, op in enumerate(strokes)]
    return dataclasses.replace(
        base, ops=base.ops + tuple(ops), entries=entries + len(ops), motion=None
    )


def _moved(op: dict, shift: float) -> dict:
    """The stroke op ``op`` ``shift`` seconds later (its times and heal)."""
    return {
        **op,
        "times": [t + shift for t in op["times"]],
        "heal": [op["heal"][0] + shift, op["heal"][1] + shift],
    }


def _continued(stirred, recipe, size: tuple[int, int]):
    """A StirredRecipe of ``recipe`` over frames of ``size`` that goes on with the
    tracker of ``stirred`` (None: a new one), under ``recipe``'s motion fields."""
    from marblevideo.motion import StirredRecipe

    new = StirredRecipe(recipe, size)
    if stirred is not None:
        stirred.tracker.spec = recipe.motion
        new.tracker = stirred.tracker
    return new


def _plain(value):
    """``value`` with NumPy numbers as Python's (for JSON)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value
