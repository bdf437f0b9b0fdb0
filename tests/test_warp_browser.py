"""The page's WebGL2 warp (marblevideo/design/web/warp.js) in a real headless
Chromium (SwiftShader): a base picture (samples/coffee.jpg) warped by each op
type agrees with the NumPy reference's render of [the base as the input + that
op] on >= 98% of pixels within 8 levels, mid-progress, at the end and while
healing; a stroke drawn in time and grown point by point (its cache of whole
steps kept) agrees at each point's time with the finished stroke. Skipped, with
the reason, when Playwright, Chromium or WebGL2 with float targets is missing."""

from __future__ import annotations

import base64
import math

import cv2
import numpy as np
import pytest
from helpers import ROOT
from warp_page import READ, answer, serve_web, set_above, setup_warp, warp_frame

from benchmarks.realtime_probe import agreement
from marblevideo.ops import recipe_types
from marblevideo.recipe.frame import geometry
from marblevideo.recipe.load import Recipe
from marblevideo.reference import ink_colors, inverse_walk, render

pytestmark = pytest.mark.tier("integration")

W, H = 240, 180
WINDOW = {"start": 0, "end": 1, "heal": [1, 2]}
TIMES = (0.5, 1.0, 1.6)
C = [120, 90]

OPS = [
    {"type": "drop", "center": C, "radius": 40, "color": "#c03020"},
    {"type": "spray", "center": [90, 70], "radius": 25, "color": [20, 200, 60]},
    {"type": "tine", "point": [30, 40], "angle": 20, "alpha": 25, "lambda": 12},
    {
        "type": "drop",
        "center": {
            "keys": [{"t": 0, "v": [60, 50], "ease": "ease-in-out"}, {"t": 2, "v": [180, 130]}]
        },
        "radius": {"keys": [{"t": 0, "v": 20, "ease": [0.3, 0, 0.2, 1]}, {"t": 1.2, "v": 45}]},
        "color": {"keys": [{"t": 0, "v": "#ff0000"}, {"t": 2, "v": "navy"}]},
    },
    {
        "type": "comb",
        "point": [10, 10],
        "angle": {"keys": [{"t": 0, "v": 0, "ease": "hold"}, {"t": 0.8, "v": 60}]},
        "spacing": 30,
        "alpha": {"keys": [{"t": 0, "v": 5, "ease": "ease-in"}, {"t": 1.5, "v": 20}]},
        "lambda": 8,
    },
    {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 24, "alpha": 14, "lambda": 6},
    {"type": "wave", "amplitude": 6, "wavelength": 40, "phase": 30, "angle": 10},
    {"type": "shift", "offset": [9, -6]},
    {
        "type": "rake",
        "point": [100, 80],
        "angle": 30,
        "alpha": 9,
        "falloff": 6,
        "spacing": 14,
        "count": 7,
    },
    {
        "type": "rake",
        "point": [100, 80],
        "angle": 0,
        "alpha": 7,
        "falloff": 5,
        "tines": [-30, 3, 20],
    },
    {"type": "circle", "center": C, "radius": 50, "alpha": 40, "lambda": 15},
    {"type": "vortex", "center": C, "alpha": 60, "lambda": 20},
    {"type": "turn", "center": C, "angle": 35},
    {"type": "stir", "center": C, "radii": [20, -45, 70], "alpha": 12, "falloff": 8},
    {"type": "stir", "center": C, "radii": [30, -60], "turn": 40, "falloff": 0.3},
    {"type": "oseen", "center": C, "circulation": 40000, "viscosity": 200, "time": 2},
    {"type": "jiggle", "angle": 30, "wavelength": 60, "phase": 20, "major": 8, "minor": 5},
    {
        "type": "stroke",
        "points": [[40, 50], [120, 60], [180, 130], [90, 150]],
        "width": 30,
        "drag": 1.5,
    },
    {"type": "stroke", "points": [[40, 90], [200, 80]], "width": 24, "tines": [-30, 0, 30]},
    {"type": "rings", "center": C, "width": 12, "count": 3, "colors": ["#203080", "#f0c000"]},
    {
        "type": "line-drops",
        "from": [40, 40],
        "to": [200, 140],
        "count": 4,
        "radius": 14,
        "colors": ["#802040"],
    },
    {
        "type": "grid-drops",
        "origin": [50, 40],
        "spacing": [50, 45],
        "size": [3, 2],
        "radius": 12,
        "angle": 10,
        "colors": ["#105010", "#e0e0e0"],
    },
    {
        "type": "scatter-drops",
        "center": C,
        "size": [150, 100],
        "count": 5,
        "radius": 10,
        "seed": 7,
        "colors": ["#000080"],
    },
    {
        "type": "scatter-drops",
        "center": C,
        "size": [150, 100],
        "count": 5,
        "radius": 10,
        "seed": 9,
        "distribution": "normal",
        "colors": ["#804000"],
    },
]


def test_every_op_type_is_tested():
    assert {op["type"] for op in OPS} == set(recipe_types())


def open_warp(browser, url: str, base: np.ndarray):
    """A page at ``url`` with a warp of ``base`` set up (the test is skipped
    without WebGL2 float targets)."""
    page = browser.new_page()
    page.goto(url + "/")
    if not answer(page, 'async () => (await import("/web/warp.js")).supported()'):
        page.close()
        pytest.skip("no WebGL2 with float render targets in this Chromium")
    assert setup_warp(page, base)
    return page


@pytest.fixture(scope="module")
def warp_pages(webgl_browser):
    """The module's page and base, and a way to open a new page when a test
    closed it (a page that stopped answering: warp_page.answer)."""
    base = cv2.cvtColor(cv2.imread(str(ROOT / "samples" / "coffee.jpg")), cv2.COLOR_BGR2RGBA)
    base = cv2.resize(base, (W, H), interpolation=cv2.INTER_AREA)
    with serve_web() as url:
        held = {"page": open_warp(webgl_browser, url, base)}

        def current():
            if held["page"].is_closed():
                held["page"] = open_warp(webgl_browser, url, base)
            return held["page"], base

        yield current
        if not held["page"].is_closed():
            held["page"].close()


@pytest.fixture
def warp_page(warp_pages):
    return warp_pages()


def reference(base: np.ndarray, op: dict, t: float, edges: str = "clamp") -> np.ndarray:
    doc = {"marblevideo": 1, "canvas": [W, H], "antialias": "none", "edges": edges, "ops": [op]}
    spec = Recipe.from_dict(doc).at(t)
    return render(spec, geometry((W, H), (W, H), (W, H)), base)


def check(page, base, op, t, edges="clamp"):
    got = warp_frame(page, op, t, base.shape, edges=edges)
    assert got is not None, f"{op['type']} at t={t}: the warp refused"
    want = reference(base, op, t, edges)
    share = agreement(got, want)
    assert share >= 0.98, f"{op['type']} at t={t}: {share:.4f} of pixels agree"
    return got, want


@pytest.mark.parametrize("op", OPS, ids=[f"{k}-{op['type']}" for k, op in enumerate(OPS)])
def test_each_op_agrees_with_the_reference(warp_page, op):
    page, base = warp_page
    op = {**op, **WINDOW}
    moved = 0.0
    for t in TIMES:
        got, _ = check(page, base, op, t)
        moved = max(moved, 1 - agreement(got, base))
    assert moved > 0.01, f"{op['type']}: the op changed nothing (the test would not see a fault)"


@pytest.mark.parametrize("edges", ["repeat", "mirror", "background"])
def test_edges(warp_page, edges):
    page, base = warp_page
    check(page, base, {"type": "shift", "offset": [70, -50]}, 0.0, edges)


def timed_stroke(n: int = 60) -> dict:
    """A curl drawn in 1.2 s, with a pause (repeated time) and a repeated point."""
    pts, times = [], []
    for i in range(n):
        a = 2.2 * math.pi * i / (n - 1)
        pts.append(
            [
                round(120 + (30 + 40 * i / n) * math.cos(a), 2),
                round(90 + (25 + 30 * i / n) * math.sin(a), 2),
            ]
        )
        times.append(round(1.2 * i / (n - 1), 4))
    pts[10] = pts[9]
    times[20] = times[19]
    return {
        "type": "stroke",
        "points": pts,
        "times": times,
        "width": 26,
        "drag": 1.2,
        "tines": [0, 18],
    }


EXTEND = """(op) => {
  if (op.points.length === 2) W.strokeBegin(op);
  W.strokeExtend(op);
  return W.strokeBuilds;
}"""


def test_a_growing_stroke_is_the_finished_stroke_at_each_time(warp_page):
    """Grown point by point with strokeBegin/strokeExtend, the map laid once."""
    page, base = warp_page
    full = timed_stroke()
    checked = (5, 12, 21, 33, 47, 59)
    builds = None
    for i in range(1, len(full["points"])):
        grown = {**full, "points": full["points"][: i + 1], "times": full["times"][: i + 1]}
        n = answer(page, EXTEND, grown)
        builds = n if builds is None else builds
        if i in checked:
            t = full["times"][i]
            got = warp_frame(page, grown, t, base.shape)
            share = agreement(got, reference(base, full, t))
            assert share >= 0.98, f"grown to point {i}, t={t}: {share:.4f} of pixels agree"
    assert n == builds, "the growing stroke's map was laid again"
    healing = {**full, "heal": [1.5, 2.5]}
    for t in (1.7, 2.2):
        check(page, base, healing, t)


def test_a_stroke_grown_frame_by_frame_redraws_all_it_changes(warp_page):
    """Each frame of a growing stroke redraws only where the new steps reach
    (the rest of the canvas is kept from the frames before): what the canvas
    holds then is the whole frame drawn afresh, and the reference. Ten points
    a frame (a hand faster than the frames): several whole steps each."""
    page, base = warp_page
    full = timed_stroke()
    for i in [*range(1, 59, 10), 59]:
        grown = {**full, "points": full["points"][: i + 1], "times": full["times"][: i + 1]}
        answer(page, EXTEND, grown)
        if i in (21, 41, 59):
            kept = np.frombuffer(base64.b64decode(answer(page, READ)), np.uint8)
            kept = kept.reshape(base.shape)
            afresh = warp_frame(page, grown, full["times"][i], base.shape)
            assert agreement(kept, afresh) >= 0.999, f"grown to point {i}"
            assert agreement(kept, reference(base, full, full["times"][i])) >= 0.98
    assert agreement(kept, base) < 0.9


@pytest.mark.parametrize("width", [0, 1e-300])
def test_a_stroke_of_endless_steps_is_refused(warp_page, width):
    """A stroke (without and with times) of width 0 (a draft the server would
    refuse) or so thin that its steps could not be counted: the warp says it
    cannot, rather than loop."""
    page, base = warp_page
    for timed in ({}, {"times": [0, 0.5]}):
        op = {"type": "stroke", "points": [[20, 20], [200, 150]], "width": width, **timed}
        assert warp_frame(page, op, 1.0, base.shape) is None


def test_a_signal_is_refused(warp_page):
    page, base = warp_page
    alpha = {"signal": "audio.level", "range": [0, 9]}
    op = {"type": "tine", "point": [0, 0], "angle": 0, "alpha": alpha, "lambda": 3}
    assert warp_frame(page, op, 0, base.shape) is None


SCALED = [
    {"type": "vortex", "center": [100, 50], "alpha": 40, "lambda": 15, **WINDOW},
    {"type": "stroke", "points": [[30, 20], [150, 40], [110, 90]], "width": 20, "tines": [0, 15]},
]


@pytest.mark.parametrize("changing", SCALED, ids=[op["type"] for op in SCALED])
def test_a_scaled_canvas_and_the_ops_above(warp_page, changing):
    """The canvas 200x100 shown at 240x180 (s = 1.2, centred 30 px down: the
    contract's geometry as toCanvas and toBase), and
    ops above the changing one given as the server's map."""
    page, base = warp_page
    canvas = (200, 100)
    geom = geometry(canvas, (W, H), (W, H))
    above = [
        {"type": "drop", "center": [40, 30], "radius": 12, "color": "#2040c0"},
        {"type": "wave", "amplitude": 4, "wavelength": 30, "phase": 0, "angle": 0},
    ]
    doc = {"marblevideo": 1, "canvas": list(canvas), "antialias": "none", "ops": above}
    spec = Recipe.from_dict(doc).at(0.5)
    ox, oy = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    kx, ky, tx, ty = geom.to_canvas
    qx, qy, ink = inverse_walk(spec, ox * kx + tx, oy * ky + ty)
    colors = ink_colors(spec) / 255.0
    amap = np.stack([qx, qy, np.zeros_like(qx), np.ones_like(qx)], axis=-1)
    amap[ink >= 0] = np.concatenate(
        [colors[ink[ink >= 0], :3], -np.ones((int((ink >= 0).sum()), 1))], 1
    )
    set_above(page, amap)
    try:
        got = warp_frame(
            page,
            changing,
            0.5,
            base.shape,
            to_canvas=list(geom.to_canvas),
            to_base=list(geom.to_input),
        )
    finally:
        set_above(page, None)
    whole = {**doc, "ops": [changing, *above]}
    want = render(Recipe.from_dict(whole).at(0.5), geom, base)
    assert agreement(got, want) >= 0.98
    assert agreement(got, base) < 0.9  # the op and the ops above show


KIND = 'async (op) => (await import("/web/warp_ops.js")).resolve(op, 0.5).kind'
SERIES = [
    # even and odd tine counts, spaced closer than 2 falloffs: dozens of tines reach a pixel
    {"type": "rake", "point": [120, 90], "angle": 25, "alpha": 6, "falloff": 5, "spacing": 7,
     "count": 24},
    {"type": "rake", "point": [110, 95], "angle": 100, "alpha": 5, "falloff": 6, "spacing": 5,
     "count": 41},
    {"type": "rake", "point": [120, 90], "angle": 0, "alpha": 9, "falloff": 4,
     "tines": [-66, -44, -22, 0, 22, 44, 66]},
    {"type": "stir", "center": C, "radii": [15, -30, 45, -60, 75, -90], "alpha": 10, "falloff": 9},
    {"type": "stir", "center": C, "radii": [80, 20, 60, 40, 100], "alpha": 8, "falloff": 12},
]  # fmt: skip


@pytest.mark.parametrize("op", SERIES, ids=[f"{op['type']}-{k}" for k, op in enumerate(SERIES)])
def test_a_long_series_in_closed_form_agrees_with_the_reference(warp_page, op):
    """Evenly spaced tines (even and odd counts) and rings (equal or alternating
    signs, given in any order) are summed in closed form, as the kernels'
    series_sum: four exponentials, whatever the count."""
    page, base = warp_page
    op = {**op, **WINDOW}
    assert answer(page, KIND, op) == (9 if op["type"] == "rake" else 10)
    moved = 0.0
    for t in TIMES:
        got, _ = check(page, base, op, t)
        moved = max(moved, 1 - agreement(got, base))
    assert moved > 0.05, f"{op['type']}: the op changed too little for the test to see a fault"


@pytest.mark.parametrize("k", [0, 1, 3])
def test_one_drop_is_drawn_from_uniforms_and_a_layout_from_its_list(warp_page, k):
    """A single drop or spray is kind 11 (its row in the uniforms: no texture fetch
    per pixel, a third of SwiftShader's frame); a layout's drops stay kind 1. Both
    are checked against the reference in test_each_op_agrees_with_the_reference."""
    page, _ = warp_page
    assert answer(page, KIND, {**OPS[k], **WINDOW}) == 11
    assert answer(page, KIND, {**OPS[20], **WINDOW}) == 1  # line-drops
