"""The recipe's ``motion`` in the designer (revision 4): over a live source
(:class:`~marblevideo.design.backdrop.LiveFeed`) the backdrop's frames stir the
ink as in ``marblevideo live``, with the same tracker
(:class:`~marblevideo.live.stirring.LiveMotion`).

- Frames: the backdrop's one taking thread hands each frame it takes, in order,
  to the tracker, with the saved recipe (its ``motion`` fields, the page's
  edits once saved), at its capture time from the source's start (a file
  source's: its time in the file, continued across loops), before the frame is
  shown; renders never feed it. A saved recipe without ``motion`` runs no
  tracker (it waits, its strokes kept, until ``motion`` comes back).
- Renders: any recipe rendered with ``motion`` (the saved one, the page's
  unsaved copy, a gesture's layers) gets the motion strokes of the newest frame
  seen, moved in time to the render's ``t`` (the page's slider, unrelated to the
  source's clock), so that they show as that frame left them
  (:meth:`~marblevideo.live.stirring.LiveMotion.over`); a solo render has none.
- Still and video backdrops have no motion: a video is shown at the slider's
  time, each frame sought (scrubbed, even while the page plays), never in order,
  so nothing is tracked; render the file (``marblevideo IN --ops R``) or play it
  live (``marblevideo live IN --preview``) to see its motion strokes.
- Saving keeps ``motion`` in the recipe as the page has it: the strokes are never
  written into the file.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from marblevideo.design.describe import describe_motion
from marblevideo.recipe import Recipe

log = logging.getLogger("marblevideo.design")

#: ``GET /api/motion`` where nothing is tracked (a blank sheet, a still, a video).
NO_MOTION = {"active": False, "t": None, "level": 0.0, "regions": [], "strokes": []}


class DesignMotion:
    """The motion of a designer over ``backdrop``; ``saved()`` gives the saved
    recipe. ``live``: the tracker's :class:`~marblevideo.live.stirring.LiveMotion`
    over a live backdrop, else None (nothing is tracked)."""

    def __init__(self, backdrop, saved: Callable[[], Recipe]):
        self.live = None
        self.error: str | None = None  # the tracker's failure (it then stops)
        self._saved = saved
        if backdrop.kind == "live":
            from marblevideo.live.stirring import LiveMotion

            self._started = backdrop.started
            self.live = LiveMotion(backdrop.source.fps)
            backdrop.seen = self._see

    def _see(self, cap) -> None:
        """One captured frame, seen by the tracker under the saved recipe."""
        if self.error is not None:
            return
        live = self.live
        t = live.frame_time(cap.media_t, cap.ts, self._started)
        try:
            live.see(self._saved(), cap.rgba if cap.luma is None else cap.luma, t)
        except Exception as exc:  # noqa: BLE001 - the backdrop goes on; said once
            self.error = f"motion: {type(exc).__name__}: {exc}"
            log.exception("motion: the tracker failed; the designer goes on without it")

    def over(self, recipe: Recipe, t: float) -> Recipe:
        """``recipe`` to render at ``t``: with the motion strokes when it has
        ``motion`` and the backdrop is live, else itself."""
        return recipe if self.live is None else self.live.over(recipe, t)

    def state(self, query: dict) -> dict:
        """``GET /api/motion``: the motion of the newest frame (``?shapes=0``: its
        regions and strokes left out), ``error`` once the tracker failed, and the
        ``fields`` the page edits."""
        if self.live is None:
            return {**NO_MOTION, "fields": describe_motion()}
        state = self.live.state(shapes=query.get("shapes", ["1"])[-1] != "0")
        if self.error is not None:
            state["error"] = self.error
        return {**state, "fields": describe_motion()}
