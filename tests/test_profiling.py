"""The profiling queue: off by default; on, each kernel's launches and device time."""

from __future__ import annotations

import pytest
from helpers import fresh_renderer

from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

pytestmark = pytest.mark.tier("fast")

RECIPE = {
    "marblevideo": 1,
    "canvas": [64, 48],
    "antialias": "none",
    "ops": [{"type": "wave", "amplitude": 5, "wavelength": 40, "phase": 0, "angle": 30}],
}


def render_twice(renderer) -> None:
    recipe = parse_recipe(RECIPE, "wave")
    geom = geometry(recipe.canvas, (64, 48), (64, 48))
    for _ in range(2):
        renderer.render(recipe.at(0.0, recipe.canvas), geom)


def test_a_profiling_renderer_times_each_kernel():
    renderer = fresh_renderer(profile=True)  # fresh: a profiling queue
    render_twice(renderer)
    times = renderer.device_queue.kernel_times()
    assert set(times) == {"marble"}  # a blank sheet, walked afresh
    count, seconds = times["marble"]
    assert count == 2 and 0 < seconds < 10
    assert renderer.device_queue.kernel_times() == {}  # counted once


def test_the_queue_does_not_profile_by_default():
    renderer = fresh_renderer()  # fresh: the session's renderer is not asked
    render_twice(renderer)
    assert renderer.device_queue.launches is None
    assert renderer.device_queue.kernel_times() == {}
