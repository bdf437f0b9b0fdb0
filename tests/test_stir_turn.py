"""``stir`` with ``turn`` (pst-marble's stir): refusals with the JSON path, the
float64 maps by hand, progress, and the kernel section against the reference."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from helpers import one_line, subprocess_env
from op_probe import run_op

from marblevideo.errors import RecipeError
from marblevideo.recipe import parse_recipe
from marblevideo.reference import forward, inverse

pytestmark = pytest.mark.tier("fast")

STIR = {"type": "stir", "center": [100, 100], "radii": [30, -60, 90], "turn": 120, "falloff": 0.2}


def stir_at(op: dict, t: float = 1.0):
    return parse_recipe({"canvas": [200, 200], "ops": [op]}, "s.json").at(t).ops[0]


@pytest.mark.parametrize(
    ("change", "path"),
    [({"alpha": 9}, "ops[0].turn"), ({"turn": None}, "ops[0]")],
    ids=["both", "neither"],
)
def test_alpha_and_turn_together_or_neither_are_refused_with_the_path(change, path):
    op = {k: v for k, v in {**STIR, **change}.items() if v is not None}
    with pytest.raises(RecipeError) as caught:
        parse_recipe({"canvas": [200, 200], "ops": [op]}, "s.json")
    assert caught.value.path == path and "alpha" in caught.value.message


def test_the_command_line_refuses_both_in_one_line(tmp_path):
    recipe = tmp_path / "both.json"
    recipe.write_text(json.dumps({"canvas": [64, 64], "ops": [{**STIR, "alpha": 3}]}))
    run = subprocess.run(
        [sys.executable, "-m", "marblevideo", "--ops", str(recipe), "-o", str(tmp_path / "o.png")],
        capture_output=True,
        text=True,
        env=subprocess_env(),
    )
    assert run.returncode == 2 and not (tmp_path / "o.png").exists()
    assert "ops[0].turn" in one_line(run)


def test_a_point_on_a_ring_turns_by_the_sum_of_the_rings_terms():
    op = stir_at(STIR)
    for big_r in (30.0, 60.0, 90.0, 0.0, 45.0):
        terms = [
            math.copysign(1, r) * math.exp(-abs(big_r - abs(r)) / (0.2 * abs(r)))
            for r in (30, -60, 90)
        ]
        theta = math.radians(120 * sum(terms))
        x, y = forward(op, np.array([100 + big_r]), np.array([100.0]))
        assert x[0] == pytest.approx(100 + big_r * math.cos(theta), abs=1e-9)
        assert y[0] == pytest.approx(100 + big_r * math.sin(theta), abs=1e-9)


def test_positive_turn_is_clockwise_on_screen_and_finite_at_the_centre():
    op = stir_at({**STIR, "radii": [40]})
    x, y = forward(op, np.array([140.0, 100.0]), np.array([100.0, 100.0]))
    assert y[0] > 100 and x[1] == 100 and y[1] == 100  # +x turns towards +y (down)


def test_inverse_undoes_forward_and_progress_scales_the_turn():
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-50, 250, 4000), rng.uniform(-50, 250, 4000)
    op = stir_at(STIR)
    bx, by = inverse(op, *forward(op, x, y))
    assert np.abs(bx - x).max() < 1e-9 and np.abs(by - y).max() < 1e-9
    half = stir_at({**STIR, "start": 0, "end": 2}, t=1.0)
    assert half.values["turn"] == pytest.approx(60.0)


def test_the_kernel_section_matches_the_reference(renderer):
    rng = np.random.default_rng(5)
    x, y = rng.uniform(0, 200, 6000), rng.uniform(0, 200, 6000)
    for op in (stir_at(STIR), stir_at({**STIR, "turn": -700, "falloff": 1.5})):
        rx, ry = inverse(op, x, y)
        for lanes in (None, 1):  # the device's width and a GPU's one pixel a work-item
            kx, ky, _ = run_op(renderer, op, x, y, lanes)
            assert np.abs(kx - rx).max() < 5e-3 and np.abs(ky - ry).max() < 5e-3
