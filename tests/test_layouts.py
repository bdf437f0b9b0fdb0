"""Drop layouts expand at load to the drops and windows the contract gives."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from helpers import ROOT

from marblevideo.errors import RecipeError
from marblevideo.ops import LAYOUTS, REGISTRY
from marblevideo.ops.layouts import MASK64, expand, splitmix64
from marblevideo.recipe import parse_recipe

pytestmark = pytest.mark.tier("fast")

CANVAS = {"canvas": [200, 150]}


def drops(layout: dict) -> list:
    return parse_recipe({**CANVAS, "ops": [layout]}, "r.json").ops


@pytest.mark.parametrize("name", list(LAYOUTS))
def test_every_layout_has_its_docs_paragraph_and_a_valid_example(name):
    docs = (ROOT / "docs" / "recipe-format.md").read_text()
    assert re.search(rf"^### `{name}`", docs, re.M)
    ops = drops(dict(LAYOUTS[name].example))
    assert ops and all(op.type == "drop" for op in ops)


def test_rings_leave_boundaries_at_whole_widths():
    """After all n drops the boundary of ring k lies at (n - k) w, colors[0] outermost."""
    n, w = 5, 7.0
    layout = {"type": "rings", "center": [100, 75], "width": w, "count": n,
              "colors": ["#111111", "#222222"]}  # fmt: skip
    ops = drops(layout)
    assert [op.params["radius"].at(0) for op in ops] == [
        w * math.sqrt(2 * (n - k) - 1) for k in range(n)
    ]
    spec = parse_recipe({**CANVAS, "ops": [layout]}, "r").at(0)
    for k, op in enumerate(spec.ops):
        r = op["radius"]
        x, y = np.array([100.0 + r]), np.array([75.0])
        for later in spec.ops[k + 1 :]:
            x, y = REGISTRY["drop"].forward(later.values, x, y)
        assert math.hypot(x[0] - 100, y[0] - 75) == pytest.approx((n - k) * w, rel=1e-12)
    assert [op["color"] for op in spec.ops] == [(17.0,) * 3, (34.0,) * 3] * 2 + [(17.0,) * 3]


def test_line_drops_run_from_a_to_b():
    layout = {"type": "line-drops", "from": [10, 20], "to": [50, 60], "count": 5, "radius": 3,
              "colors": ["#ff0000"]}  # fmt: skip
    assert [op.params["center"].at(0) for op in drops(layout)] == [
        (10 + 10 * k, 20 + 10 * k) for k in range(5)
    ]
    one = drops({**layout, "count": 1})
    assert [op.params["center"].at(0) for op in one] == [(10.0, 20.0)]


def test_grid_drops_are_serpentine_and_turn_with_the_angle():
    layout = {"type": "grid-drops", "origin": [10, 10], "spacing": [5, 8], "size": [3, 2],
              "radius": 2, "colors": ["#ff0000"]}  # fmt: skip
    centres = [op.params["center"].at(0) for op in drops(layout)]
    assert centres == [(10, 10), (15, 10), (20, 10), (20, 18), (15, 18), (10, 18)]
    turned = [op.params["center"].at(0) for op in drops({**layout, "angle": 90})]
    assert turned[1] == pytest.approx((10, 15)) and turned[3] == pytest.approx((2, 20))
    with pytest.raises(RecipeError, match=r"ops\[0\]\.size: must make at most 4096 drops"):
        drops({**layout, "size": [100, 100]})


def test_splitmix64_is_the_published_stream():
    """The first output of SplitMix64 seeded with 0 is 0xE220A8397B1DCDAF (Vigna)."""
    assert next(splitmix64(0)) == (0xE220A8397B1DCDAF >> 11) / 2**53
    a, b = splitmix64(2**63 - 1), splitmix64(2**63 - 1)
    assert [next(a) for _ in range(5)] == [next(b) for _ in range(5)]
    assert MASK64 == 2**64 - 1


def test_scatter_drops_follow_the_seed_and_distribution():
    layout = {"type": "scatter-drops", "center": [100, 75], "size": [80, 40], "count": 200,
              "radius": 1, "seed": 42, "colors": ["#000000"]}  # fmt: skip
    centres = np.array([op.params["center"].at(0) for op in drops(layout)])
    draws = splitmix64(42)
    u1, u2 = next(draws), next(draws)
    assert tuple(centres[0]) == pytest.approx((100 + (u1 - 0.5) * 80, 75 + (u2 - 0.5) * 40))
    assert (np.abs(centres - [100, 75]) <= [40, 20]).all()
    normal = np.array(
        [op.params["center"].at(0) for op in drops({**layout, "distribution": "normal"})]
    )
    g = math.sqrt(-2 * math.log(1 - u1))
    expected = (100 + g * math.cos(2 * math.pi * u2) * 80 / math.sqrt(8),
                75 + g * math.sin(2 * math.pi * u2) * 40 / math.sqrt(8))  # fmt: skip
    assert tuple(normal[0]) == pytest.approx(expected)
    assert np.std(normal[:, 0]) == pytest.approx(80 / math.sqrt(8), rel=0.2)
    other = np.array([op.params["center"].at(0) for op in drops({**layout, "seed": 43})])
    assert not np.allclose(other, centres)


def test_windows_are_cut_in_order_or_shared():
    layout = {**LAYOUTS["line-drops"].example, "start": 1, "end": 3}
    ops = drops(layout)
    n = len(ops)
    assert [(op.start, op.end) for op in ops] == [
        pytest.approx((1 + 2 * k / n, 1 + 2 * (k + 1) / n)) for k in range(n)
    ]
    shared = drops({**LAYOUTS["line-drops"].example, "start": 2})
    assert {(op.start, op.end) for op in shared} == {(2.0, None)}


@pytest.mark.parametrize(
    "layout, message",
    [
        ({"width": {"keys": [{"t": 0, "v": 3}]}}, r"ops\[0\]\.width: expected a number"),
        ({"count": 0}, r"ops\[0\]\.count: must be >= 1, got 0"),
        ({"colors": []}, r"ops\[0\]\.colors: expected a list of 1\.\.256 colors"),
        ({"colour": ["#000000"]}, r"unknown field 'colour' \(did you mean 'colors'\?\)"),
    ],
)
def test_layout_fields_are_constants_with_clear_errors(layout, message):
    rings = {**LAYOUTS["rings"].example, **layout}
    if "colour" in layout:
        del rings["colors"]
    with pytest.raises(RecipeError, match=message):
        parse_recipe({**CANVAS, "ops": [rings]}, "r.json")


def test_expand_keeps_what_the_layout_says():
    assert len(expand(dict(LAYOUTS["grid-drops"].example))) == 12
