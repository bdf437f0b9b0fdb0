"""A video job's take (``--automation FILE`` on a file render) and the motion pass
that a split render analyses first (docs/recipe-format.md, "motion").

- The take is the recipe's JSON with every motion stroke made appended to its ops
  as an ordinary ``stroke`` and without ``motion``
  (:meth:`marblevideo.motion.StirredRecipe.take_document`); rendering it over the
  same input gives the same frames. A job without motion strokes (no ``motion``, a
  still, a blank sheet) writes the recipe's JSON without ``motion``.
- :func:`motion_pass` sees every frame of a whole input in time order as the video
  job would (the same frames, times and luma: :class:`~marblevideo.media.decode.Reader`'s
  luma plane, decoded only, nothing marbled), so that the segments of a split render
  can each render the take (:func:`take_recipe`) and equal a single render.

Files are written atomically (a temporary file beside the target, renamed; ``-y``
to replace one).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import os
from pathlib import Path

from marblevideo.errors import UsageError
from marblevideo.media.decode import Reader, open_input
from marblevideo.media.inputs import Input
from marblevideo.media.output import atomic_output, check_output
from marblevideo.motion import StirredRecipe
from marblevideo.recipe import Recipe, parse_recipe
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


def take_document(document: dict, stirred: StirredRecipe | None) -> dict:
    """The take of ``document`` after a job whose motion ``stirred`` saw its frames
    (None: no frame was seen, no stroke)."""
    if stirred is not None:
        return stirred.take_document(document)
    return {k: copy.deepcopy(v) for k, v in document.items() if k != "motion"}


def write_take(path, document: dict, overwrite: bool) -> dict:
    """Write the take ``document`` to ``path`` atomically; the document."""
    with atomic_output(path, overwrite) as tmp:
        tmp.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
    return document


def motion_pass(
    source: str | os.PathLike | Input, recipe: Recipe, fit, size
) -> StirredRecipe | None:
    """Every frame of video ``source`` seen by a :class:`StirredRecipe` of ``recipe``
    (which has ``motion``) rendered at ``size`` with ``fit``, as a single render's
    transform sees them; None for an input without frames."""
    stirred = None
    with open_input(source) as container:
        reader = Reader(container, None, None, {}, i420=True, luma=True)
        for item in reader.items():
            frame = item.luma if item.luma is not None else item.rgba
            if stirred is None:
                stirred = StirredRecipe(recipe, (frame.shape[1], frame.shape[0]), fit, size)
            stirred.see(frame, item.t)
    return stirred


def take_recipe(recipe: Recipe, stirred: StirredRecipe | None) -> Recipe:
    """``recipe`` with every stroke of ``stirred``'s take appended to its ops as
    ordinary strokes and no ``motion``: what the take renders."""
    strokes = [] if stirred is None else stirred.tracker.take()
    plain = dataclasses.replace(recipe, motion=None)
    if not strokes:
        return plain
    ops = parse_recipe({"ops": strokes}, recipe.source).ops
    base, entries = len(plain.ops), plain.entries
    ops = tuple(
        dataclasses.replace(op, index=base + n, entry=entries + n) for n, op in enumerate(ops)
    )
    return dataclasses.replace(plain, ops=plain.ops + ops, entries=entries + len(ops))
