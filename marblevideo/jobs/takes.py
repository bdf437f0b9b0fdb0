"""A video job's take (``--automation FILE`` on a file render) and the frames a
segment of a split render sees before its own (docs/recipe-format.md, "motion").

- The take is the recipe's JSON with every motion stroke made appended to its ops
  as an ordinary ``stroke`` and without ``motion``
  (:meth:`marblevideo.motion.StirredRecipe.take_document`); rendering it over the
  same input gives the same frames. A job without motion strokes (no ``motion``, a
  still, a blank sheet) writes the recipe's JSON without ``motion``.
- :func:`watch_before` shows a segment's transform the frames before the segment
  (decoded only, their luma planes, nothing marbled), so that its motion goes on
  from where a single render's is there: a split render's frames equal a single
  render's, strokes included.

Files are written atomically (a temporary file beside the target, renamed; ``-y``
to replace one).
"""

from __future__ import annotations

import copy
import json
import os
from pathlib import Path

from marblevideo.errors import UsageError
from marblevideo.jobs.transforms import PipelinedTransform
from marblevideo.media.decode import Reader, open_input
from marblevideo.media.output import atomic_output, check_output
from marblevideo.motion import StirredRecipe
from marblevideo.recipe import Recipe
from marblevideo.recipe.load import read_recipe


def recipe_document(recipe) -> dict:
    """The JSON a take starts from: ``recipe`` as a dict (itself) or a file (read
    again); UsageError for a built :class:`Recipe`, whose JSON is not kept."""
    if isinstance(recipe, dict):
        return recipe
    if isinstance(recipe, Recipe):
        raise UsageError("automation: give the recipe as a file or a dict (the take is its JSON)")
    return read_recipe(recipe)[0]


def check_take(path, overwrite: bool, others) -> None:
    """Refuse a take's ``path`` before any work: it names one of ``others`` (the
    recipe, the input, the output), or exists without ``overwrite`` (exit 2)."""
    for other in others:
        if other is not None and Path(os.fspath(other)).resolve() == Path(path).resolve():
            raise UsageError(f"--automation: {path} is also {other}; name another")
    check_output(path, overwrite)


def start_take(path, recipe, document: dict | None, overwrite: bool, others) -> dict | None:
    """Before any work, for a take to write at ``path`` (None: no take, None returned):
    the JSON it starts from (``document``, else :func:`recipe_document` of
    ``recipe``), its path checked (:func:`check_take`)."""
    if path is None:
        return None
    document = recipe_document(recipe) if document is None else document
    check_take(path, overwrite, others)
    return document


def take_document(document: dict, stirred: StirredRecipe | list | None) -> dict:
    """The take of ``document`` after a job whose motion ``stirred`` saw its frames
    (or the list of every stroke it made; None: no frame was seen, no stroke)."""
    if isinstance(stirred, StirredRecipe):
        return stirred.take_document(document)
    take = {k: copy.deepcopy(v) for k, v in document.items() if k != "motion"}
    if stirred:
        take["ops"] = [*take.get("ops", []), *stirred]
    return take


def write_take(path, document: dict, overwrite: bool) -> dict:
    """Write the take ``document`` to ``path`` atomically; the document."""
    with atomic_output(path, overwrite) as tmp:
        tmp.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
    return document


def watch_before(source, transform: PipelinedTransform, start: float | None) -> int:
    """Show ``transform`` (one that :attr:`~PipelinedTransform.watches`) every frame of
    video ``source`` before ``start`` seconds, in time order, as a whole render's
    transform stage shows them (the reader's luma plane, else the RGBA frame), without
    marbling them: a segment's motion then starts from the state a single render has
    there. The number of frames seen."""
    if start is None:
        return 0
    seen = 0
    with open_input(source) as container:
        for item in Reader(container, None, start, {}, i420=True, luma=True).items():
            transform.watch(item.luma if item.luma is not None else item.rgba, item.t)
            seen += 1
    return seen
