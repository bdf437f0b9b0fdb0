"""Marbling the last captured frame again when the recipe shown changes between
captures (a preview from the designer's page, a save), for the preview's JPEG
only, so the page sees an edit without waiting for the source's next frame.

- Only the preview: the outputs (virtual camera, streams, NDI, the recording)
  get captured frames, each once, at the source's pace; a redraw is not counted
  as a frame shown (``frames``, the rates, the capture-to-JPEG latency). The
  motion tracker does not see the frame again: a redraw renders with the
  strokes the last capture left
  (:meth:`~marblevideo.live.stirring.LiveMotion.over`), so the take
  (``--automation``: the saved recipe and the motion strokes) is as without it.
- It never costs a captured frame: it is made whenever the render loop is idle
  (no captured frame waiting) and it ends before the frame after the next is
  captured (now + a render <= the last capture's time + 2 periods): the next
  captured frame, come meanwhile, is rendered right after it, up to a render
  late, and taken before a newer one could replace it in the mailbox; the
  renders being shorter than the period, the loop is back on time within a few
  frames. (Before, the rule also wanted the next frame's render done by then:
  now + 2 renders; with a preview's renders 20-60 ms at 30 fps that almost
  never held, 0-5 redraws in a 2 s drag.) A source slower than that (a camera
  at 5 fps, a file) is redrawn at once.
"""

from __future__ import annotations

import numpy as np


class LastFrame:
    """The last frame captured (as captured: before the mirror), its capture time
    and the seconds a render takes (the session's median of the last seconds: a
    render slowed once by other programs does not stop the redraws), for a
    redraw; ``count``: redraws made."""

    def __init__(self, fps: float):
        self.period = 1.0 / fps if fps > 0 else 0.0
        self.rgba: np.ndarray | None = None
        self.ts = 0.0
        self.render_s = 0.0
        self.count = 0

    def captured(self, rgba: np.ndarray, ts: float, render_s: float) -> None:
        self.rgba, self.ts, self.render_s = rgba, ts, render_s

    def allows(self, now: float, waiting: bool) -> bool:
        """Whether a redraw at ``now`` (time.monotonic()) costs no captured frame
        (``waiting``: one is waiting to be rendered)."""
        if self.rgba is None or waiting:
            return False
        return self.period <= 0 or now + self.render_s <= self.ts + 2 * self.period


def redrawn(marbler, motion, rgba: np.ndarray, shown: float) -> np.ndarray:
    """``rgba`` marbled by ``marbler`` at the clock's time ``shown``, with the
    motion strokes ``motion`` (:class:`~marblevideo.live.stirring.LiveMotion`)
    has now, moved to ``shown``, when its recipe has ``motion``."""
    recipe = motion.over(marbler.recipe, shown)
    if recipe is not marbler.recipe:
        marbler = marbler.with_recipe(recipe)
    return marbler.render(rgba, shown, animated=True)
