"""The reference's inverse walk, bilinear sampler and renderer, against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from marblevideo import reference
from marblevideo.recipe.antialias import PATTERNS
from marblevideo.recipe.frame import EDGE_MODES, FrameSpec, OpState, geometry
from marblevideo.reference import forward, inverse_walk, render, sample_bilinear

pytestmark = pytest.mark.tier("fast")

RED, BLUE, GREEN = (255.0, 0.0, 0.0), (0.0, 0.0, 255.0), (0.0, 200.0, 0.0)
WHITE = (255.0, 255.0, 255.0)


def drop(cx: float, cy: float, r: float, color=RED) -> OpState:
    return OpState("drop", {"center": (cx, cy), "radius": r, "color": color})


def spray(cx: float, cy: float, r: float, color=GREEN) -> OpState:
    return OpState("spray", {"center": (cx, cy), "radius": r, "color": color})


def tine(alpha: float = 8.0) -> OpState:
    return OpState("tine", {"point": (0.0, 50.0), "angle": 0.0, "alpha": alpha, "lambda": 4.0})


def spec(*ops: OpState, antialias="none", edges="clamp", canvas=(100.0, 100.0), bg=WHITE):
    return FrameSpec(tuple(ops), bg, antialias, edges, canvas)


# --- inverse_walk


def test_later_drop_wins_and_pushes_earlier_ink_out() -> None:
    """Drop 0 (r 10) then drop 1 (r 20), both at (50, 50): hand-computed radii."""
    s = spec(drop(50, 50, 10, RED), drop(50, 50, 20, BLUE))
    # distance 0 and 19: inside drop 1; 21: sqrt(21^2 - 20^2) = 6.4 < 10, drop 0;
    # 25: sqrt(25^2 - 20^2) = 15 > 10, then drop 0 undone: sqrt(15^2 - 10^2) = sqrt(125).
    x = 50.0 + np.array([0.0, 19.0, 21.0, 25.0])
    x0, y0, ink = inverse_walk(s, x, np.full(4, 50.0))
    np.testing.assert_array_equal(ink, [1, 1, 0, -1])
    assert x0[3] == pytest.approx(50.0 + math.sqrt(125.0), abs=1e-12) and y0[3] == 50.0


def test_ink_test_is_strict() -> None:
    """|P - C| = r exactly is not ink (hypot(3, 4) == 5 exactly); it maps to C."""
    x0, y0, ink = inverse_walk(spec(drop(0, 0, 5)), 3.0, 4.0)
    assert ink == -1 and (x0, y0) == (0.0, 0.0)


def test_spray_colors_without_deforming() -> None:
    s = spec(drop(50, 50, 10), spray(80, 80, 5))
    only_drop = spec(drop(50, 50, 10))
    x, y = np.array([81.0, 70.0, 20.0]), np.array([79.0, 50.0, 33.0])
    x0, y0, ink = inverse_walk(s, x, y)
    ex, ey, eink = inverse_walk(only_drop, x, y)
    np.testing.assert_array_equal(ink, [1, -1, -1])
    np.testing.assert_array_equal(x0[1:], ex[1:])
    np.testing.assert_array_equal(y0[1:], ey[1:])
    np.testing.assert_array_equal(eink, [-1, -1, -1])


def test_zero_radius_ink_is_absent() -> None:
    s = spec(drop(50, 50, 0.0), spray(50, 50, 0.0))
    x0, y0, ink = inverse_walk(s, [50.0, 51.0], [50.0, 50.0])
    np.testing.assert_array_equal(ink, [-1, -1])
    np.testing.assert_array_equal(x0, [50.0, 51.0])


def test_a_deformed_drop_holds_its_forward_image() -> None:
    """[drop, tine]: the tine drags the drop; the moved centre is ink of op 0 and keeps
    the coordinates it had on reaching the drop (the tine undone: C itself)."""
    s = spec(drop(30, 50, 5), tine())
    moved = forward(tine(), 30.0, 50.0)
    assert moved[0] == pytest.approx(38.0)
    x0, y0, ink = inverse_walk(s, *moved)
    assert ink == 0
    assert x0 == pytest.approx(30.0, abs=1e-12) and y0 == pytest.approx(50.0, abs=1e-12)
    # [tine, drop]: the drop lands on the combed sheet, undeformed.
    _, _, ink = inverse_walk(spec(tine(), drop(30, 50, 5)), [34.9, 35.1], [50.0, 50.0])
    np.testing.assert_array_equal(ink, [1, -1])


# --- sample_bilinear on a hand-made 3 x 2 image

# Red channel: row 0 = 10, 50, 90; row 1 = 130, 170, 210. Green = 255 - red.
# Blue is the column index * 100, alpha 255 except 120 at (row 1, col 2).
IMAGE = np.zeros((2, 3, 4), dtype=np.uint8)
IMAGE[..., 0] = [[10, 50, 90], [130, 170, 210]]
IMAGE[..., 1] = 255 - IMAGE[..., 0]
IMAGE[..., 2] = [[0, 100, 200], [0, 100, 200]]
IMAGE[..., 3] = [[255, 255, 255], [255, 255, 120]]
BG = (1.0, 2.0, 3.0)
BG4 = np.array([1.0, 2.0, 3.0, 255.0])
PX = IMAGE.astype(np.float64)


def test_centres_return_pixels_exactly() -> None:
    ys, xs = np.mgrid[0:2, 0:3] + 0.5
    for mode in EDGE_MODES:
        got = sample_bilinear(IMAGE, xs.ravel(), ys.ravel(), mode, BG)
        np.testing.assert_array_equal(got, PX.reshape(-1, 4))


def test_between_centres_blends_linearly() -> None:
    got = sample_bilinear(IMAGE, [1.0, 0.75, 1.0, 2.5], [0.5, 0.5, 1.0, 0.75], "clamp", BG)
    np.testing.assert_allclose(got[0], (PX[0, 0] + PX[0, 1]) / 2)
    np.testing.assert_allclose(got[1], 0.75 * PX[0, 0] + 0.25 * PX[0, 1])
    np.testing.assert_allclose(got[2], PX[:, :2].mean(axis=(0, 1)))
    np.testing.assert_allclose(got[3], 0.75 * PX[0, 2] + 0.25 * PX[1, 2])
    assert got.shape == (4, 4) and got.dtype == np.float64


# Tap index (column) -> column it reads, per mode, W = 3 (mirror period 6).
TAPS = np.array([-7, -4, -3, -2, -1, 0, 1, 2, 3, 4, 5, 6, 8])
COLUMNS = {
    "clamp": [0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2],
    "repeat": [2, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 2],
    "mirror": [0, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 2],
}


@pytest.mark.parametrize("mode", ["clamp", "repeat", "mirror"])
def test_edge_modes_pick_columns_and_rows(mode: str) -> None:
    got = sample_bilinear(IMAGE, TAPS + 0.5, np.full(TAPS.shape, 0.5), mode, BG)
    np.testing.assert_array_equal(got, PX[0, COLUMNS[mode]])
    rows = np.array([-3, -2, -1, 2, 3, 4])
    got = sample_bilinear(IMAGE, np.full(rows.shape, 2.5), rows + 0.5, mode, BG)
    expected = {
        "clamp": [0, 0, 0, 1, 1, 1],
        "repeat": [1, 0, 1, 0, 1, 0],
        "mirror": [1, 1, 0, 1, 0, 0],
    }
    np.testing.assert_array_equal(got, PX[expected[mode], 2])


def test_background_mode_fills_outside_taps() -> None:
    got = sample_bilinear(IMAGE, TAPS + 0.5, np.full(TAPS.shape, 0.5), "background", BG)
    inside = (TAPS >= 0) & (TAPS < 3)
    np.testing.assert_array_equal(got[inside], PX[0, TAPS[inside]])
    np.testing.assert_array_equal(got[~inside], np.broadcast_to(BG4, (int((~inside).sum()), 4)))
    got = sample_bilinear(IMAGE, [0.5, 2.5], [-0.5, 2.5], "background", BG)
    np.testing.assert_array_equal(got, [BG4, BG4])


def test_blends_across_the_border_per_mode() -> None:
    """x = 0 sits halfway between tap -1 and tap 0; the corner (0, 0) mixes four taps."""
    p0, p1, p2 = PX[0]
    for mode, expected in [
        ("clamp", p0),
        ("repeat", (p2 + p0) / 2),
        ("mirror", p0),
        ("background", (BG4 + p0) / 2),
    ]:
        np.testing.assert_allclose(sample_bilinear(IMAGE, 0.0, 0.5, mode, BG), expected)
    corner = sample_bilinear(IMAGE, 0.0, 0.0, "background", BG)
    np.testing.assert_allclose(corner, (3 * BG4 + PX[0, 0]) / 4)
    corner = sample_bilinear(IMAGE, 0.0, 0.0, "repeat", BG)
    np.testing.assert_allclose(corner, (PX[1, 2] + PX[1, 0] + PX[0, 2] + PX[0, 0]) / 4)


def test_unknown_edge_mode_is_refused() -> None:
    with pytest.raises(ValueError, match="edges"):
        sample_bilinear(IMAGE, 0.5, 0.5, "wrap", BG)


# --- render


def random_image(h: int, w: int, channels: int = 4, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (h, w, channels), dtype=np.uint8)


@pytest.mark.parametrize("mode", EDGE_MODES)
def test_identity_render_returns_the_image(mode: str) -> None:
    img = random_image(5, 7)
    s = spec(antialias="none", edges=mode, canvas=(7.0, 5.0))
    np.testing.assert_array_equal(render(s, geometry((7.0, 5.0), (7, 5)), img), img)


def test_identity_render_of_rgb_returns_rgb() -> None:
    img = random_image(5, 7, channels=3, seed=1)
    out = render(spec(canvas=(7.0, 5.0)), geometry((7.0, 5.0), (7, 5)), img)
    assert out.shape == (5, 7, 3)
    np.testing.assert_array_equal(out, img)


@pytest.mark.parametrize("aa", sorted(PATTERNS))
@pytest.mark.parametrize("mode", ["clamp", "repeat", "mirror"])
def test_every_pattern_keeps_a_constant_image(aa: str, mode: str) -> None:
    img = np.empty((6, 9, 4), dtype=np.uint8)
    img[...] = (37, 201, 90, 180)
    out = render(
        spec(antialias=aa, edges=mode, canvas=(9.0, 6.0)), geometry((9.0, 6.0), (9, 6)), img
    )
    np.testing.assert_array_equal(out, img)


def test_upscaled_input_by_hand() -> None:
    """A 2 x 2 input shown 4 x 4: output centres land at input 0.25, 0.75, 1.25, 1.75,
    so the per-axis weights of the right pixel are 0, 1/4, 3/4, 1 (clamp)."""
    img = np.zeros((2, 2, 4), dtype=np.uint8)
    img[..., 0] = [[0, 64], [128, 192]]
    img[..., 3] = 255
    geom = geometry((2.0, 2.0), (4, 4), input_size=(2, 2))
    out = render(spec(canvas=(2.0, 2.0)), geom, img)
    w = np.array([0.0, 0.25, 0.75, 1.0])
    expected = 64 * w[None, :] + 128 * w[:, None]
    np.testing.assert_array_equal(out[..., 0], expected)
    np.testing.assert_array_equal(out[..., 3], 255)


def test_blank_sheet_drop_inside_outside_and_antialiased_edge() -> None:
    geom = geometry((100.0, 100.0), (100, 100))
    out = render(spec(drop(50, 50, 20), antialias="rgss", bg=(0.0, 0.0, 255.0)), geom)
    assert out.shape == (100, 100, 4)
    np.testing.assert_array_equal(out[50, 50], [255, 0, 0, 255])
    np.testing.assert_array_equal(out[50, 60], [255, 0, 0, 255])
    np.testing.assert_array_equal(out[5, 5], [0, 0, 255, 255])
    np.testing.assert_array_equal(out[50, 90], [0, 0, 255, 255])
    red = out[..., 0].astype(int)
    partial = (red > 0) & (red < 255)
    assert partial.any()
    # Every partial pixel straddles the circle: its centre is within one pixel of it.
    j, i = np.nonzero(partial)
    assert np.abs(np.hypot(i + 0.5 - 50, j + 0.5 - 50) - 20).max() < 1.0
    # rgss has 4 equal weights: 1, 2 or 3 of them red (63.75, 127.5, 191.25 rounded).
    assert set(np.unique(red[partial])) <= {64, 128, 191}
    # Without antialiasing there are only the two colors.
    hard = render(spec(drop(50, 50, 20), bg=(0.0, 0.0, 255.0)), geom)
    assert set(np.unique(hard[..., 0])) == {0, 255}


def test_spray_over_an_image() -> None:
    """Spray paints its disc opaque and leaves every other pixel of the image as it was."""
    img = random_image(40, 40, seed=2)
    s = spec(spray(20, 20, 5, BLUE), canvas=(40.0, 40.0))
    out = render(s, geometry((40.0, 40.0), (40, 40)), img)
    j, i = np.mgrid[0:40, 0:40] + 0.5
    inside = np.hypot(i - 20, j - 20) < 5
    np.testing.assert_array_equal(out[inside], np.broadcast_to([0, 0, 255, 255], (inside.sum(), 4)))
    np.testing.assert_array_equal(out[~inside], img[~inside])


def test_tine_moves_paint_along_its_direction() -> None:
    """A horizontal ramp (red = 4 * column) under a tine along +x (alpha 8, lambda 4, on
    y = 50): pixel (i, j) shows the input at x = i + 0.5 - shift(j), i.e. 4 (i - shift)."""
    img = np.zeros((100, 64, 4), dtype=np.uint8)
    img[..., 0] = 4 * np.arange(64)[None, :]
    img[..., 3] = 255
    out = render(spec(tine(), canvas=(64.0, 100.0)), geometry((64.0, 100.0), (64, 100)), img)
    j = np.arange(100)[:, None]
    i = np.arange(16, 48)[None, :]
    shift = 8.0 * 4.0 / (np.abs(j + 0.5 - 50.0) + 4.0)
    expected = 4.0 * (i - shift)
    assert np.abs(out[:, 16:48, 0] - expected).max() <= 0.5 + 1e-9


def test_canvas_fit_letterboxes_and_centres() -> None:
    """Canvas 100 x 50 in 200 x 200: s = 2, offset (0, 50); the canvas centre (50, 25)
    lands at output (100, 100) and a drop of radius 10 becomes one of radius 20."""
    geom = geometry((100.0, 50.0), (200, 200))
    assert geom.to_canvas == (0.5, 0.5, 0.0, -25.0)
    ops = (drop(50, 25, 10, RED), spray(10, 10, 3, GREEN), spray(50, -10, 5, BLUE))
    out = render(spec(*ops, antialias="rgss", canvas=(100.0, 50.0)), geom)
    ink = out[..., :3].astype(int)
    for j, i in [(100, 100), (100, 119), (100, 80), (119, 100), (80, 100)]:
        np.testing.assert_array_equal(ink[j, i], RED)
    for j, i in [(100, 121), (100, 78), (121, 100), (78, 100)]:
        np.testing.assert_array_equal(ink[j, i], WHITE)
    np.testing.assert_array_equal(ink[70, 20], GREEN)  # canvas (10, 10) -> output (20, 70)
    np.testing.assert_array_equal(ink[20, 20], WHITE)
    # The ops act on the whole plane: a drop above the canvas shows in the letterbox.
    np.testing.assert_array_equal(ink[30, 100], BLUE)  # canvas (50, -10) -> output (100, 30)


def test_chunking_does_not_change_the_picture(monkeypatch: pytest.MonkeyPatch) -> None:
    img = random_image(30, 40, seed=3)
    s = spec(
        drop(20, 15, 6),
        OpState("vortex", {"center": (20.0, 15.0), "alpha": 30.0, "lambda": 5.0}),
        antialias="quincunx",
        edges="mirror",
        canvas=(40.0, 30.0),
    )
    geom = geometry((40.0, 30.0), (40, 30))
    whole = render(s, geom, img)
    monkeypatch.setattr(reference.shading, "CHUNK_POINTS", 37)
    np.testing.assert_array_equal(render(s, geom, img), whole)


def test_rounding_is_floor_plus_half() -> None:
    """Half ink (255), half background (2) is 128.5: floor(v + 0.5) gives 129, where
    truncation or round-half-to-even would give 128."""
    # quincunx at a pixel whose centre is ink and corners are not: 0.5 * 255 + 0.5 * bg.
    geom = geometry((10.0, 10.0), (10, 10))
    out = render(spec(spray(5.5, 5.5, 0.6, RED), antialias="quincunx", bg=(2.0, 0.0, 0.0)), geom)
    assert out[5, 5, 0] == 129


def test_bad_images_and_modes_are_refused() -> None:
    geom = geometry((4.0, 4.0), (4, 4))
    with pytest.raises(ValueError, match="uint8"):
        render(spec(canvas=(4.0, 4.0)), geom, np.zeros((4, 4, 4), dtype=np.float32))
    with pytest.raises(ValueError, match="uint8"):
        render(spec(canvas=(4.0, 4.0)), geom, np.zeros((4, 4), dtype=np.uint8))
    with pytest.raises(ValueError, match="edges"):
        render(spec(edges="wrap", canvas=(4.0, 4.0)), geom)
    with pytest.raises(ValueError, match="antialias"):
        render(spec(antialias="msaa", canvas=(4.0, 4.0)), geom)


@pytest.mark.parametrize("aa", sorted(PATTERNS))
def test_each_subsample_sits_at_its_offset_with_its_weight(aa: str) -> None:
    """A tiny spray on one subsample point (5.5 + dx, 5.5 + dy) of pixel (5, 5) colors
    that pixel by exactly that subsample's weight."""
    geom = geometry((10.0, 10.0), (10, 10))
    for dx, dy, weight in PATTERNS[aa]:
        s = spec(spray(5.5 + dx, 5.5 + dy, 1e-3, RED), antialias=aa, bg=(0.0, 0.0, 0.0))
        out = render(s, geom)
        assert out[5, 5, 0] == math.floor(255 * weight + 0.5), (dx, dy)
