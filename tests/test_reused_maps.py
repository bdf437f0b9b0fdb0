"""Reused maps: frames over an input whose values repeat fetch from a table.

The table path is checked against a fresh walk of the same frame (within one
level) and against the NumPy reference, for every AA pattern and edges mode.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import fresh_renderer
from recipes import EDGES, PATTERNS, make_image, random_recipe
from tolerances import KERNEL_SHARE

from marblevideo.opencl.selfcheck import agreement
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")


@pytest.fixture(scope="module")
def fresh():
    return fresh_renderer(reuse_maps=False)


def frame(seed: int, size=(113, 89), t: float = 10.0):
    recipe = parse_recipe(random_recipe(seed), "static.json")
    image = make_image(96 + seed % 5, 72 + seed % 3, seed, alpha=seed % 2 == 0)
    geom = geometry(recipe.canvas, size, (image.shape[1], image.shape[0]))
    return recipe.at(t), geom, image


def max_diff(a: np.ndarray, b: np.ndarray) -> int:
    return int(np.abs(a.astype(np.int16) - b.astype(np.int16)).max())


@pytest.mark.parametrize("seed", range(24))  # every AA pattern x every edges mode
def test_repeated_frame_comes_from_the_table_within_one_level(fresh, seed):
    spec, geom, image = frame(seed)
    assert (spec.antialias, spec.edges) == (PATTERNS[seed % 6], EDGES[seed // 6 % 4])
    renderer = fresh_renderer()  # fresh (as in every test here): no table filled yet
    first = renderer.render(spec, geom, image)
    assert not renderer.last_reused
    again = renderer.render(spec, geom, image)
    assert renderer.last_reused
    walked = fresh.render(spec, geom, image)
    assert np.array_equal(first, walked)
    assert max_diff(again, walked) <= 1
    assert agreement(again, reference_render(spec, geom, image)) >= KERNEL_SHARE


@pytest.mark.parametrize("lanes", [1, 4, 8])
def test_every_lane_width_reuses_maps_alike(fresh, lanes):
    renderer = fresh_renderer(lanes=lanes, chains=1 if lanes == 1 else 2)
    for seed in (3, 10, 17):
        spec, geom, image = frame(seed, (61, 47))
        renderer.render(spec, geom, image)
        again = renderer.render(spec, geom, image)
        assert renderer.last_reused
        assert max_diff(again, fresh.render(spec, geom, image)) <= 1


def test_new_pictures_through_one_table(fresh):
    """A static recipe over a video: the table stays, the pictures change."""
    spec, geom, _ = frame(5, (90, 70))
    renderer = fresh_renderer()
    pictures = [make_image(97, 72, s, alpha=True) for s in range(4)]
    outs = [renderer.render(spec, geom, p) for p in pictures]
    assert renderer.last_reused
    for picture, out in zip(pictures, outs, strict=True):
        assert max_diff(out, fresh.render(spec, geom, picture)) <= 1
    assert max_diff(outs[1], outs[2]) > 10  # the frames differ, as their pictures do


def test_any_change_walks_afresh(fresh):
    recipe = parse_recipe(random_recipe(11), "animated.json")
    image = make_image(64, 48, 2)
    geom = geometry(recipe.canvas, (64, 48), (64, 48))
    renderer = fresh_renderer()
    renderer.render(recipe.at(10.0), geom, image)
    renderer.render(recipe.at(10.0), geom, image)
    assert renderer.last_reused
    changes = [
        (recipe.at(0.5), geom, image),  # other values
        (recipe.at(0.5), geometry(recipe.canvas, (64, 48), (64, 48), (0, 0, 20, 20)), image),
        (recipe.at(0.5), geom, make_image(65, 48, 2)),  # other input size
    ]
    for spec, g, picture in changes:
        out = renderer.render(spec, g, picture)
        assert not renderer.last_reused
        assert np.array_equal(out, fresh.render(spec, g, picture))
        again = renderer.render(spec, g, picture)
        assert renderer.last_reused
        assert max_diff(again, out) <= 1


def test_static_frames_come_from_the_table_from_the_first(fresh):
    """static=True (a static recipe over a video): the first frame already fills and
    uses the table; a frame with other values under the same promise walks the
    table again rather than serving stale maps."""
    spec, geom, image = frame(7)
    other, _, _ = frame(8)
    renderer = fresh_renderer()
    for values in (spec, spec, other, other):
        out = renderer.render(values, geom, image, static=True)
        assert renderer.last_reused
        assert max_diff(out, fresh.render(values, geom, image)) <= 1
    assert max_diff(out, fresh.render(spec, geom, image)) > 10  # other values, other frame


def test_identity_through_the_table_is_exact():
    image = make_image(67, 41, 5, alpha=True)
    recipe = parse_recipe(
        {"marblevideo": 1, "canvas": [67, 41], "antialias": "none", "ops": []}, "id.json"
    )
    geom = geometry(recipe.canvas, (67, 41), (67, 41))
    renderer = fresh_renderer()
    renderer.render(recipe.at(0), geom, image)
    assert np.array_equal(renderer.render(recipe.at(0), geom, image), image)
    assert renderer.last_reused


def test_table_over_the_limit_or_switched_off_walks_every_frame():
    spec, geom, image = frame(4)
    big = fresh_renderer()
    big.tables.limit = 1024  # this frame's table needs 4 * 89 * 128 * 4 bytes
    off = fresh_renderer(reuse_maps=False)
    for renderer in (big, off):
        first = renderer.render(spec, geom, image)
        assert np.array_equal(renderer.render(spec, geom, image), first)
        assert not renderer.last_reused
