"""The recipe's ``motion`` in the designer (revision 4): over a live source
(:class:`~marblevideo.design.backdrop.LiveFeed`) or a video the backdrop's
frames stir the ink as in ``marblevideo live`` and in file renders, with the
same tracker (:class:`~marblevideo.live.stirring.LiveMotion`).

- Live frames: the backdrop's one taking thread hands each frame it takes, in order,
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
- Over a video (:class:`VideoMotion`) the strokes are a file render's: the
  page shows the frame at the slider's time (sought), so the tracker reads the
  file itself, in order from its start, up to the render's ``t`` (its frames,
  their times in the file and their decoded luma planes, as a file render sees
  them: the same strokes as ``marblevideo IN --ops R``). Playing goes forward
  cheaply; a render at an earlier time (a scrub back, a loop), or of a recipe
  with other ``motion`` fields or canvas, starts again from the file's start and
  costs every frame before ``t``, decoded and measured (the analysis alone is
  about 7.6 ms a frame at 720p on two cores). A still has no motion.
- Saving keeps ``motion`` in the recipe as the page has it: the strokes are never
  written into the file.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from marblevideo.design.describe import describe_motion
from marblevideo.recipe import Recipe

log = logging.getLogger("marblevideo.design")

#: ``GET /api/motion`` where nothing is tracked (a blank sheet, a still; a video
#: before its first render of a recipe with ``motion``).
NO_MOTION = {"active": False, "t": None, "level": 0.0, "regions": [], "strokes": []}


class DesignMotion:
    """The motion of a designer over ``backdrop``; ``saved()`` gives the saved
    recipe. ``live``: the tracker's :class:`~marblevideo.live.stirring.LiveMotion`
    over a live backdrop; ``video``: the :class:`VideoMotion` of a video backdrop;
    both None over a blank sheet or a still (nothing is tracked)."""

    def __init__(self, backdrop, saved: Callable[[], Recipe]):
        self.live = None
        self.error: str | None = None  # the tracker's failure (it then stops)
        self._saved = saved
        self.video = VideoMotion(backdrop.name) if backdrop.kind == "video" else None
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
        ``motion`` and the backdrop is live or a video, else itself."""
        if self.video is not None:
            return self.video.over(recipe, t)
        return recipe if self.live is None else self.live.over(recipe, t)

    def close(self) -> None:
        """The video's reader closed (a live backdrop is its opener's to close)."""
        if self.video is not None:
            self.video.close()

    def state(self, query: dict) -> dict:
        """``GET /api/motion``: the motion of the newest frame (``?shapes=0``: its
        regions and strokes left out), ``error`` once the tracker failed, and the
        ``fields`` the page edits."""
        live = self.live if self.video is None else self.video.live
        if live is None:
            return {**NO_MOTION, "fields": describe_motion()}
        state = live.state(shapes=query.get("shapes", ["1"])[-1] != "0")
        if self.error is not None:
            state["error"] = self.error
        return {**state, "fields": describe_motion()}


class VideoMotion:
    """The motion a file render of the video ``name`` makes, up to any time: one
    :class:`~marblevideo.live.stirring.LiveMotion` (``live``; None before the
    first render with ``motion``) sees the file's frames in order, at their times
    in the file, as their decoded luma planes."""

    def __init__(self, name: str):
        self.name = name
        self.live = None
        self._lock = threading.Lock()
        self._key = None  # (motion, canvas) of the recipe the frames were seen with
        self._recipe: Recipe | None = None
        self._container = None
        self._frames = iter(())
        self._ahead = None  # the first frame not seen yet (after the last render's t)

    def over(self, recipe: Recipe, t: float) -> Recipe:
        """``recipe`` (with ``motion``) and the motion strokes of the frames up to
        ``t``, as the last of them left them; ``recipe`` itself without ``motion``."""
        if recipe.motion is None:
            return recipe
        with self._lock:
            key = (recipe.motion, recipe.canvas)
            seen = None if self.live is None else self.live.t
            if key != self._key or (seen is not None and seen > t + 1e-6):
                self._restart(recipe, key)
            self._advance(t)
            live = self.live
        return live.over(recipe, t)

    def _restart(self, recipe: Recipe, key) -> None:
        """From the file's start, with ``recipe``'s motion fields."""
        from marblevideo.live.stirring import LiveMotion
        from marblevideo.media.decode import Reader, open_input

        self._close()
        self._container = open_input(self.name)
        reader = Reader(self._container, None, None, {}, i420=True, luma=True)  # no RGBA made
        self._frames = reader.items()
        self.live, self._key, self._recipe, self._ahead = LiveMotion(0.0), key, recipe, None

    def _advance(self, t: float) -> None:
        """Show the tracker the frames of times up to ``t`` not seen yet."""
        while True:
            item = self._ahead or next(self._frames, None)
            if item is None:  # the file's end
                return
            if item.t > t + 1e-6:
                self._ahead = item
                return
            self._ahead = None
            self.live.see(self._recipe, item.rgba if item.luma is None else item.luma, item.t)

    def close(self) -> None:
        with self._lock:
            self._close()

    def _close(self) -> None:
        if self._container is not None:
            self._container.close()
            self._container, self._frames, self._ahead = None, iter(()), None
