"""The bundled samples: valid recipes, and the Figure-6 design matches the reference."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from tolerances import KERNEL_LEVELS, KERNEL_SHARE

from marblevideo.recipe import load_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

SAMPLES = Path(__file__).resolve().parent.parent / "samples"


@pytest.mark.parametrize(
    "name", sorted(p.name for p in SAMPLES.glob("*.json") if p.name != "recipe.schema.json")
)
def test_samples_load_and_point_to_the_schema(name):
    recipe = load_recipe(SAMPLES / name)
    assert recipe.ops
    assert json.loads((SAMPLES / name).read_text())["$schema"] == "./recipe.schema.json"


def test_bundled_schema_is_the_published_one():
    from marblevideo.recipe.schema import schema

    assert json.loads((SAMPLES / "recipe.schema.json").read_text()) == schema()


def test_figure6_at_1024_matches_the_reference(renderer):
    recipe = load_recipe(SAMPLES / "figure6.json")
    spec = recipe.at(recipe.end_time())
    geom = geometry(recipe.canvas, (1024, 1024))
    ours = renderer.render(spec, geom)
    ref = reference_render(spec, geom)
    diff = np.abs(ours.astype(np.int16) - ref.astype(np.int16)).max(axis=2)
    assert (diff <= KERNEL_LEVELS).mean() >= KERNEL_SHARE
    assert len(np.unique(ours.reshape(-1, 4), axis=0)) > 20  # a real design, not a flat sheet


def test_outputs_get_the_usual_file_mode(tmp_path):
    import os

    from marblevideo.media.output import atomic_output

    umask = os.umask(0o022)
    try:
        with atomic_output(tmp_path / "x.png") as tmp:
            tmp.write_bytes(b"x")
    finally:
        os.umask(umask)
    assert (tmp_path / "x.png").stat().st_mode & 0o777 == 0o644
