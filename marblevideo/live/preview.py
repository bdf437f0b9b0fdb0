"""An unsaved recipe a live session shows while the designer's page draws
(``PUT /api/preview``: the stroke being drawn, applied to the live frames as it
grows, :mod:`marblevideo.design.live`).

A preview names the recipe version it was drawn on; it is shown only while that
version is the file's (a save, the page's own on release or any other, makes it
stale), and only for :data:`TTL` seconds after it was last sent (the page sends
it again while the hand holds still), so a page that goes away mid-drag leaves
nothing behind. Each new preview replaces the one before: the newest wins.
"""

from __future__ import annotations

import threading
import time

from marblevideo.recipe import Recipe, parse_recipe

#: Seconds a preview is shown after it was last sent.
TTL = 4.0


class LivePreview:
    """The newest preview: :meth:`put` sets or clears it, :meth:`current` says
    which recipe to render for the file's version."""

    def __init__(self, source: str):
        self.source = source  # the recipe file's name, for errors
        self._lock = threading.Lock()
        self._recipe: Recipe | None = None
        self._base = 0
        self._sent = 0.0
        self.serial = 0  # counts previews taken: a key for the marbler built for each

    def put(self, doc: object, version: object) -> int:
        """Show ``doc`` (validated: RecipeError, one line, when not a recipe) while
        the file is at ``version``; ``doc`` None clears the preview. Its serial (the
        live frames that show it are tagged with it)."""
        if not isinstance(version, int) or isinstance(version, bool):
            raise ValueError(f"preview: version must be the recipe's version, got {version!r}")
        recipe = None if doc is None else parse_recipe(doc, f"{self.source} (preview)")
        with self._lock:
            self._recipe, self._base, self._sent = recipe, version, time.monotonic()
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
