"""The designer's preview is rendered as a draft (no antialiasing) by the live
session, like the page's own frames while a hand moves; the save that ends the
gesture shows the recipe with its antialiasing (:mod:`marblevideo.live.preview`).

A real session (the test pattern, the OpenCL renderer) marbles one captured
frame: with a preview, the frame equals the draft render of the preview and not
its antialiased render; after the save, the antialiased one."""

from __future__ import annotations

import dataclasses
import json
import time

import numpy as np
import pytest

from marblevideo.live.session import LiveSession
from marblevideo.live.sources import TestPattern
from marblevideo.marbler import Marbler
from marblevideo.recipe import parse_recipe

pytestmark = pytest.mark.tier("integration")

COMB = {"type": "comb", "point": [0, 0], "angle": 70, "spacing": 14, "alpha": 9, "lambda": 4}
DROP = {"type": "drop", "center": [48, 32], "radius": 20, "color": "#e63946"}
RECIPE = {"marblevideo": 1, "antialias": "rgss", "ops": [DROP]}


def _off(a: np.ndarray, b: np.ndarray) -> int:
    """The largest difference of two frames (1-2: a walk's order of sums)."""
    return int(np.abs(a.astype(int) - b.astype(int)).max())


def test_a_preview_is_a_draft_and_the_save_is_antialiased(tmp_path, renderer):
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    source = TestPattern((96, 64), 5.0)
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    frame = source.frame(0.0, 0)
    doc = {**RECIPE, "ops": [DROP, COMB]}
    recipe = parse_recipe(doc)
    full = Marbler(recipe, renderer=renderer).render(frame, 0.0, animated=True)
    draft = Marbler(dataclasses.replace(recipe, antialias="none"), renderer=renderer)
    draft = draft.render(frame, 0.0, animated=True)
    assert _off(full, draft) > 20  # they differ

    session.show_preview(doc, session.file.snapshot()[2])
    shown = session.show(frame, time.monotonic())
    assert _off(shown, draft) <= 2 < _off(shown, full)
    assert session.recipe.antialias == "rgss"  # the file's recipe is as saved

    session.put(doc)  # the gesture's save: as it is, antialiased
    shown = session.show(frame, time.monotonic())
    assert _off(shown, full) <= 2 < _off(shown, draft)
