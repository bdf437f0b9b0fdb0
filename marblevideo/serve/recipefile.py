"""A recipe file edited over HTTP (the designer's FILE, and ``live``'s recipe):
read, validated, saved atomically, watched.

:class:`RecipeFile` holds the recipe as JSON (what the page edits) beside the
validated :class:`~marblevideo.recipe.Recipe` (what renders). A change is
validated first (the one-line JSON-path error of the recipe format, and
nothing saved when it fails), then written to a temporary file beside FILE and
renamed over it, so FILE is never half-written. Changes made to FILE by other
programs are picked up by :meth:`RecipeFile.check_reload`; a save that does not
validate keeps the previous recipe and is reported as :attr:`error`.
"""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path

from marblevideo.errors import RecipeError, UsageError
from marblevideo.media.output import atomic_output
from marblevideo.recipe import Recipe, parse_recipe
from marblevideo.recipe.load import read_recipe

#: Canvas of a new blank-sheet recipe.
DEFAULT_CANVAS = (1024, 768)


def new_recipe(canvas: tuple[float, float] | None) -> dict:
    """A recipe with no ops yet: a white sheet of ``canvas`` (None: the input's size)."""
    doc: dict = {"marblevideo": 1}
    if canvas is not None:
        doc["canvas"] = [canvas[0], canvas[1]]
    doc["background"] = "#ffffff"
    doc["ops"] = []
    return doc


def save_recipe(path: str | os.PathLike, doc: object) -> Recipe:
    """Validate ``doc`` and write it to ``path`` atomically (a temporary file beside
    it, renamed over it); the Recipe. RecipeError, nothing written, when invalid."""
    return save_stamped(path, doc)[0]


def save_stamped(path: str | os.PathLike, doc: object, check=None) -> tuple[Recipe, tuple | None]:
    """:func:`save_recipe`, and the saved file's stamp (:func:`file_stamp`), taken
    before the rename moves it into place: a change another program makes at once
    is never taken for this save. ``check(recipe)`` may refuse it (RecipeError) first."""
    recipe = parse_recipe(doc, str(path))
    if check is not None:
        check(recipe)
    text = json.dumps(doc, indent=2) + "\n"
    with atomic_output(path, overwrite=True) as tmp:
        tmp.write_text(text, encoding="utf-8")
        stamp = file_stamp(tmp)
    return recipe, stamp


def file_stamp(path: Path) -> tuple[int, int, int] | None:
    """What tells a file's versions apart (mtime, size, inode: an atomic save is a
    new file); None when it cannot be read."""
    try:
        st = path.stat()
    except OSError:
        return None
    return (st.st_mtime_ns, st.st_size, st.st_ino)


class RecipeFile:
    """FILE as the designer and ``live`` see it: :attr:`doc` (JSON), :attr:`recipe`
    (validated), :attr:`version` (counts accepted changes, from a page or from
    disk), :attr:`error` (the last change on disk that was refused, or None).

    A missing FILE is made (a blank sheet of ``canvas``) when ``create``, else
    refused as :func:`~marblevideo.recipe.load_recipe` refuses it. ``notify``
    gets the one-line message of each change on disk that is refused; ``check``
    (of a Recipe, raising RecipeError) refuses what the session cannot show (a
    blank sheet's recipe without a canvas), in a save and in a change on disk."""

    def __init__(
        self,
        path: str | os.PathLike,
        canvas: tuple[float, float] | None = None,
        *,
        create: bool = True,
        notify=None,
        check=None,
    ):
        self.path = Path(path)
        self._check = check or (lambda recipe: None)
        self._lock = threading.Lock()
        self._notify = notify or (lambda message: None)
        self.error: str | None = None
        self.version = 1
        if self.path.exists() or not create:
            self.doc, self.recipe = read_recipe(self.path)  # a bad FILE stops the start (exit 2)
        else:
            self.doc = new_recipe(canvas)
            self.recipe = save_recipe(self.path, self.doc)
        self._stamp = self._file_stamp()

    def _file_stamp(self):
        return file_stamp(self.path)

    def snapshot(self) -> tuple[dict, Recipe, int]:
        """(doc, recipe, version) as they are now."""
        with self._lock:
            return self.doc, self.recipe, self.version

    def answer(self) -> tuple[int, dict]:
        """``GET /api/recipe``: (200, the recipe's JSON), or while the last change
        on disk was refused (:attr:`error`), (409, ``{"error": the one-line
        message with its JSON path, "last_good": the recipe still in use,
        "version": its version}``), so no client takes it for FILE's contents."""
        with self._lock:
            if self.error is None:
                return 200, self.doc
            return 409, {"error": self.error, "last_good": self.doc, "version": self.version}

    def put(self, doc: object) -> int:
        """Validate ``doc``, save it atomically and make it current; its version.
        RecipeError (nothing saved) when it is not a valid recipe."""
        with self._lock:
            recipe, self._stamp = save_stamped(self.path, doc, self._check)
            self.doc, self.recipe = doc, recipe
            self.version += 1
            self.error = None
            return self.version

    def check_reload(self) -> bool:
        """Take FILE's contents if another program changed it; whether it did. A
        change that does not validate is kept out and reported in :attr:`error`.
        FILE is looked at under the lock a save holds, so a save of our own is
        never taken for another program's, and a save made while the file is
        read wins."""
        with self._lock:
            stamp = self._file_stamp()
            if stamp is None or stamp == self._stamp:
                return False
            self._stamp = stamp
        try:
            doc, recipe = read_recipe(self.path)
            self._check(recipe)
            error = None
        except (RecipeError, UsageError, ValueError) as exc:
            error = f"{exc} (keeping the previous recipe)"
        with self._lock:
            if self._stamp != stamp:
                return False
            if error is None:
                self.doc, self.recipe = doc, recipe
                self.version += 1
            self.error = error
        if error is not None:
            self._notify(error)
        return error is None
