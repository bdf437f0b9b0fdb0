"""An unsaved recipe a live session shows while the designer's page draws
(``PUT /api/preview``: the stroke being drawn, applied to the live frames as it
grows, :mod:`marblevideo.design.live`).

A preview names the recipe version it was drawn on; it is shown only while that
version is the file's (a save, the page's own on release or any other, makes it
stale), and only for :data:`TTL` seconds after it was last sent (the page sends
it again while the hand holds still), so a page that goes away mid-drag leaves
nothing behind. Each new preview replaces the one before: the newest wins. A
page may have two sends on their way, so each may name when it was ``sent``
(the page's clock, ms): one that comes after a newer send was taken (within
:data:`OVERTAKE` seconds) is not taken.
"""

from __future__ import annotations

import threading
import time

from marblevideo.recipe import Recipe, parse_recipe

#: Seconds a preview is shown after it was last sent.
TTL = 4.0
#: Seconds within which a send stamped older than the last one taken is refused.
OVERTAKE = 1.0


class LivePreview:
    """The newest preview: :meth:`put` sets or clears it, :meth:`current` says
    which recipe to render for the file's version."""

    def __init__(self, source: str):
        self.source = source  # the recipe file's name, for errors
        self._lock = threading.Lock()
        self._recipe: Recipe | None = None
        self._base = 0
        self._sent = 0.0  # time.monotonic() of the last preview taken
        self._stamp = float("-inf")  # its ``sent`` (the page's ms)
        self.serial = 0  # counts previews taken: a key for the marbler built for each

    def put(self, doc: object, version: object, sent: object = None) -> int:
        """Show ``doc`` (validated: RecipeError, one line, when not a recipe) while
        the file is at ``version``; ``doc`` None clears the preview. Its serial (the
        live frames that show it are tagged with it), or 0 when a newer send (by
        ``sent``, the page's ms) was taken: overtaken, it is not shown."""
        if not isinstance(version, int) or isinstance(version, bool):
            raise ValueError(f"preview: version must be the recipe's version, got {version!r}")
        if sent is not None and (not isinstance(sent, (int, float)) or isinstance(sent, bool)):
            raise ValueError(f"preview: sent must be a time in ms, got {sent!r}")
        recipe = None if doc is None else parse_recipe(doc, f"{self.source} (preview)")
        with self._lock:
            now = time.monotonic()
            if sent is not None and sent <= self._stamp and now - self._sent < OVERTAKE:
                return 0
            self._stamp = self._stamp if sent is None else sent
            self._recipe, self._base, self._sent = recipe, version, now
            self.serial += 1
            return self.serial

    def current(self, version: int, now: float | None = None) -> tuple[Recipe, int] | None:
        """(the preview's recipe, its serial) to render while the file is at
        ``version`` (at time.monotonic() ``now``), or None: render the file's recipe."""
        with self._lock:
            fresh = (time.monotonic() if now is None else now) - self._sent < TTL
            if self._recipe is None or self._base != version or not fresh:
                return None
            return self._recipe, self.serial

    def shown(self, recipe: Recipe, version: int) -> tuple[Recipe, object, int]:
        """(the recipe to render, a key for it, the preview's serial or 0) while the
        file's is ``recipe`` at ``version``: the preview's when :meth:`current` has
        one (key ("preview", serial)), else the file's (key ``version``, serial 0)."""
        drawing = self.current(version)
        if drawing is None:
            return recipe, version, 0
        return drawing[0], ("preview", drawing[1]), drawing[1]
