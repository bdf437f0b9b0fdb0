"""Presets (issue 22): the bundled recipes by name, and their optional top-level
``description``, which the renderer ignores."""

from __future__ import annotations

import pytest

from marblevideo import RecipeError, parse_recipe

DESIGN = {"canvas": [16, 12], "ops": [{"type": "drop", "center": [8, 6], "radius": 4,
                                       "color": "#123456"}]}  # fmt: skip


def test_a_description_is_kept_and_changes_no_frame():
    described = parse_recipe({**DESIGN, "description": "One blue drop."})
    assert described.description == "One blue drop."
    assert parse_recipe(DESIGN).description == ""
    assert described.at(0) == parse_recipe(DESIGN).at(0)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("x" * 201, "too long: at most 200 characters, got 201"),
        (["a"], "expected a string, got a list of 1"),
    ],
)
def test_a_bad_description_is_one_line_with_its_path(value, message):
    with pytest.raises(RecipeError) as info:
        parse_recipe({**DESIGN, "description": value}, "r.json")
    assert str(info.value) == f"r.json: description: {message}"
