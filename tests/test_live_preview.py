"""The live session's preview of an unsaved recipe (the stroke being drawn on
the designer's page, :mod:`marblevideo.live.preview`): shown while the file is
at the version it was drawn on, replaced by a newer one, cleared, stale after a
save or TTL seconds; an invalid one refused with its one-line error."""

from __future__ import annotations

import time

import pytest

from marblevideo.errors import RecipeError
from marblevideo.live import preview
from marblevideo.live.preview import LivePreview

pytestmark = pytest.mark.tier("fast")

STROKE = {"type": "stroke", "points": [[10, 10], [50, 20]], "times": [1.0, 1.5]}


def doc(*ops) -> dict:
    return {"marblevideo": 1, "canvas": [100, 80], "ops": list(ops)}


def test_the_newest_preview_is_shown_until_a_save_or_a_clear():
    p = LivePreview("live.json")
    assert p.current(3) is None
    p.put(doc(STROKE), 3)
    recipe, first = p.current(3)
    assert len(recipe.ops) == 1
    assert p.current(4) is None  # a save made version 4: the preview is stale
    p.put(doc(STROKE, STROKE), 3)  # the newest wins
    recipe, second = p.current(3)
    assert len(recipe.ops) == 2 and second != first
    p.put(None, 3)
    assert p.current(3) is None
    p.put(doc(STROKE), 3)
    later = time.monotonic() + preview.TTL + 0.1
    assert p.current(3, later) is None  # not sent again for TTL seconds: gone


def test_an_invalid_preview_is_refused_and_the_one_before_kept():
    p = LivePreview("live.json")
    p.put(doc(STROKE), 1)
    with pytest.raises(RecipeError, match=r"ops\[0\]"):
        p.put(doc({**STROKE, "times": [2.0, 1.0]}), 1)
    with pytest.raises(ValueError, match="version"):
        p.put(doc(STROKE), "1")
    assert p.current(1) is not None


def test_a_send_overtaken_by_a_newer_one_is_not_shown():
    """Two sends on their way: the older, taken after the newer, is refused
    (serial 0); a clear refuses the older sends still on their way too."""
    p = LivePreview("live.json")
    newer = p.put(doc(STROKE, STROKE), 1, sent=2000.5)
    assert newer and p.put(doc(STROKE), 1, sent=1999.0) == 0
    recipe, serial = p.current(1)
    assert len(recipe.ops) == 2 and serial == newer
    assert p.put(doc(STROKE), 1, sent=2100.0) > newer  # a later send is taken
    assert p.put(doc(STROKE, STROKE), 1) > 0  # unstamped: taken as it comes
    p.put(None, 1, sent=2300.0)
    assert p.put(doc(STROKE), 1, sent=2200.0) == 0 and p.current(1) is None
    with pytest.raises(ValueError, match="sent"):
        p.put(doc(STROKE), 1, sent="soon")
