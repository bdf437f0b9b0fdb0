"""Seamless tiles: with ``edges: repeat``, a tileable input and ops whose displacement
is periodic over the canvas, a 2 x 2 tiling of the render has no seam."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from helpers import ROOT

from marblevideo.marbler import Marbler
from marblevideo.recipe import parse_recipe

pytestmark = pytest.mark.tier("fast")


def seam_ratio(img: np.ndarray) -> float:
    """Discontinuity across the tile boundary of a 2 x 2 tiling, relative to the
    typical difference between neighbouring columns/rows inside the tile (1 = no seam)."""
    a = img[..., :3].astype(np.float64)
    inside_x = np.abs(np.diff(a, axis=1)).mean()
    inside_y = np.abs(np.diff(a, axis=0)).mean()
    across_x = np.abs(a[:, 0] - a[:, -1]).mean()  # column W-1 next to column 0 of the next tile
    across_y = np.abs(a[0] - a[-1]).mean()
    return max(across_x / inside_x, across_y / inside_y)


@pytest.fixture(scope="module")
def stripes():
    bgr = cv2.imread(str(ROOT / "samples" / "stripes.png"))
    return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGBA)


@pytest.fixture(scope="module")
def tile_doc():
    return json.loads((ROOT / "samples" / "tile.json").read_text())


def test_sample_tile_has_no_seam(renderer, stripes, tile_doc):
    img = Marbler(parse_recipe(tile_doc), renderer).render(stripes)
    assert seam_ratio(img) < 1.25


@pytest.mark.parametrize(
    "op, key, value",
    [(0, "spacing", 60.0), (2, "wavelength", 250.0), (3, "angle", 10.0), (4, "wavelength", 100.0)],
)
def test_a_non_periodic_op_shows_a_seam(renderer, stripes, tile_doc, op, key, value):
    doc = json.loads(json.dumps(tile_doc))
    doc["ops"][op][key] = value
    img = Marbler(parse_recipe(doc), renderer).render(stripes)
    assert seam_ratio(img) > 1.5


def test_clamp_edges_break_the_tile(renderer, stripes, tile_doc):
    doc = dict(tile_doc, edges="clamp")
    img = Marbler(parse_recipe(doc), renderer).render(stripes)
    assert seam_ratio(img) > 1.5
