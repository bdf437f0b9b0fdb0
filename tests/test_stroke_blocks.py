"""The stroke kernel's culling (marblevideo.ops.stepblocks, kernels/ops/stroke.cl):
steps walked in blocks of BLOCK_STEPS, a block skipped where no lane is inside
its circle, a step where none is within 3w/2 of it, a turn where none is within
w. Skipping is exact: on strokes of many blocks whose steps cross the
work-items' edges (and points put just inside the circles), the kernel's points
are the same bit for bit as with circles that skip nothing, in work-items of one
chain and of four (the section walks them together), and they are the float64
inverse within the section's tolerance."""

from __future__ import annotations

import numpy as np
import pytest
from op_probe import run_op
from tolerances import KERNEL_SHARE

from marblevideo.opencl.program import pack_params
from marblevideo.opencl.selfcheck import agreement
from marblevideo.ops import op_def, stepblocks, stroke, stylus
from marblevideo.ops.stepblocks import BLOCK_FLOATS, BLOCK_STEPS, block_rows
from marblevideo.ops.stroke import STEP_FLOATS, acting_steps
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import FrameSpec, geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

STROKE = op_def("stroke")
CANVAS = [300, 200]
_ZIGZAG = [[10 + 14 * k, 30 + 140 * (k % 2)] for k in range(21)]
_LOOP = [
    [round(150 + 80 * np.cos(a) + 9 * a, 3), round(100 + 70 * np.sin(2 * a), 3)]
    for a in np.linspace(0, 7, 40)
]
_TIMES = [float(t) for t in np.linspace(0, 2, 21)]
#: Strokes of many blocks (a thin zigzag: over 200 blocks), a comb (its tines'
#: steps interleaved in the blocks), a loop that crosses itself, and a timed
#: zigzag mid-gesture (its first blocks the finished stroke's, then a partial step);
#: each with the time it is walked at.
CASES = {
    "zigzag": ({"points": _ZIGZAG, "width": 5.5, "drag": 2.2}, 0.0),
    "comb": ({"points": _ZIGZAG[:8], "width": 4, "drag": -1.3, "tines": [-9, -3, 3, 9]}, 0.0),
    "loop": ({"points": _LOOP, "width": 23, "drag": -3.5}, 0.0),
    "timed": ({"points": _ZIGZAG, "width": 7, "drag": 4, "times": _TIMES}, 1.23),
}  # fmt: skip
IDS = list(CASES)


def op_of(case: str, **more):
    doc, t = CASES[case]
    doc = {**doc, **more}
    recipe = parse_recipe({"canvas": CANVAS, "ops": [{"type": "stroke", **doc}]}, "blocks.json")
    return recipe.at(t).ops[0]


def _forget():
    stroke.layout.cache_clear()
    stroke._rows.cache_clear()
    stylus.whole_steps.cache_clear()
    stylus._whole_blocks.cache_clear()


@pytest.fixture
def culling_off(monkeypatch):
    """Circles that hold the whole canvas (no block is ever skipped), for the
    test's duration; the packing caches forgotten before and after."""
    _forget()
    monkeypatch.setattr(stepblocks, "RADIUS_MARGIN", 1e6)
    yield
    monkeypatch.undo()
    _forget()


def circles(op) -> tuple[np.ndarray, np.ndarray]:
    """The packed circles (float32, (m, 3)) and the steps' ends (n, 2, 2) A and B."""
    packed = pack_params(FrameSpec((op,), (0.0, 0.0, 0.0), "none", "clamp", (1.0, 1.0)))
    row = packed.params
    at, n = int(row[0]), int(row[1])
    m = -(-n // BLOCK_STEPS)
    data = packed.lists[at + n * STEP_FLOATS : at + n * STEP_FLOATS + m * BLOCK_FLOATS]
    centres, halves, _ = acting_steps(op.values)
    assert len(centres) == n and data.size == m * BLOCK_FLOATS
    return data.reshape(m, BLOCK_FLOATS), np.stack([centres + halves, centres - halves], axis=1)


def probe_points(op, blocks: np.ndarray, ends: np.ndarray):
    """A grid over the canvas (16 consecutive points a row's run, so work-items
    straddle the steps), and points just inside the reach of the ends farthest
    from their block's centre and just inside every block's circle."""
    y, x = np.mgrid[-10:210:0.83, -10:310:0.91]
    w = float(op.values["width"])
    pts = [np.stack([x.ravel() + 0.013, y.ravel() + 0.007], axis=1)]
    for j, (mx, my, _) in enumerate(blocks.astype(np.float64)):
        e = ends[j * BLOCK_STEPS : (j + 1) * BLOCK_STEPS].reshape(-1, 2)
        away = e - (mx, my)
        away /= np.maximum(np.hypot(*away.T), 1e-12)[:, None]
        pts.append(e + away * w * (1 - 2.0**-20))
        pts.append(e + away * w * (1 + 2.0**-20))
        r = float(np.sqrt(blocks[j, 2])) * (1 - 1e-6)
        a = np.linspace(0, 2 * np.pi, 16, endpoint=False)
        pts.append(np.stack([mx + r * np.cos(a), my + r * np.sin(a)], axis=1))
    p = np.concatenate(pts).astype(np.float32)
    return p[:, 0].copy(), p[:, 1].copy()


@pytest.mark.parametrize("case", IDS)
def test_every_step_end_and_its_reach_lies_inside_its_blocks_circle(case):
    op = op_of(case)
    blocks, ends = circles(op)
    w = float(op.values["width"])
    assert len(blocks) >= 4
    for j, (mx, my, r2) in enumerate(blocks.astype(np.float64)):
        e = ends[j * BLOCK_STEPS : (j + 1) * BLOCK_STEPS].reshape(-1, 2)
        far = np.hypot(e[:, 0] - mx, e[:, 1] - my).max()
        assert (far + w) ** 2 < r2  # the float32 circle holds every end's reach
        assert np.sqrt(r2) <= (far + w) * 1.001 + 0.1  # and is no looser than its margin
    centres, halves, _ = acting_steps(op.values)
    fresh = block_rows(centres, halves, w).astype(np.float32)
    assert np.array_equal(blocks, fresh)  # blocks taken from the cache are laid afresh alike


@pytest.mark.parametrize("case", IDS)
@pytest.mark.parametrize("lanes,chains", [(None, 1), (None, 4), (1, 1), (1, 3)])
def test_culling_moves_no_point_differently(renderer, case, lanes, chains, request):
    op = op_of(case)
    x, y = probe_points(op, *circles(op))
    culled = run_op(renderer, op, x, y, lanes, chains)
    request.getfixturevalue("culling_off")
    blocks, _ = circles(op)
    assert blocks[:, 2].min() > 1e12  # circles that skip nothing
    kept = run_op(renderer, op, x, y, lanes, chains)
    assert np.hypot(culled[0] - x, culled[1] - y).max() > 1  # the stroke moved points
    for a, b in zip(culled, kept, strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("case", IDS)
def test_four_chains_walk_the_float64_inverse(renderer, case):
    """At a gentler drag: at the cases' own, points dragged along hundreds of
    steps of a thin stroke part from the float64 walk by float32 rounding (the
    same points with culling or without, as above)."""
    op = op_of(case, drag=0.7)
    x, y = probe_points(op, *circles(op))
    kx, ky, ink = run_op(renderer, op, x, y, None, 4)
    rx, ry = STROKE.inverse(op.values, x.astype(np.float64), y.astype(np.float64))
    assert (ink < 0).all()
    err = np.hypot(kx - rx, ky - ry)
    assert (err <= 2e-3).mean() >= 0.999, err.max()
    still = (rx == x) & (ry == y)
    assert still.mean() > 0.2 and np.array_equal(kx[still], x[still])
    assert np.array_equal(ky[still], y[still])


@pytest.mark.parametrize("loop_walk", [False, True], ids=["unrolled", "loop"])
def test_a_picture_through_strokes_of_many_blocks_renders_as_the_reference(loop_walk):
    from helpers import fresh_renderer

    ops = [{"type": "stroke", **CASES[c][0], "drag": 0.7} for c in ("zigzag", "loop", "timed")]
    recipe = parse_recipe({"canvas": CANVAS, "antialias": "rgss", "ops": ops}, "blocks.json")
    spec, geom = recipe.at(1.23), geometry(recipe.canvas, (150, 100), (64, 48))
    yy, xx = np.mgrid[0:48, 0:64]
    image = np.stack([xx * 4, yy * 5, (xx ^ yy) * 8 % 256], axis=-1).astype(np.uint8)
    ours = fresh_renderer(loop_walk=loop_walk).render(spec, geom, image)
    share = agreement(ours[..., :3], reference_render(spec, geom, image))
    assert share >= KERNEL_SHARE, share


def _stretch(inverse, x: np.ndarray, y: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """How much the float64 ``inverse`` (x, y -> x, y) stretches the plane at each
    point: the Frobenius norm of its Jacobian, by central differences."""
    ax, ay = inverse(x + h, y)
    bx, by = inverse(x - h, y)
    cx, cy = inverse(x, y + h)
    dx, dy = inverse(x, y - h)
    return np.sqrt((ax - bx) ** 2 + (ay - by) ** 2 + (cx - dx) ** 2 + (cy - dy) ** 2) / (2 * h)


@pytest.mark.parametrize("case", ["zigzag", "loop", "timed"])
def test_at_full_drag_the_kernel_parts_from_float64_only_where_the_walk_stretches(renderer, case):
    """At the cases' own drag (2.2 to 4), a thin stroke stretches the plane a
    thousand-fold and more in places: there a step's float32 rounding is
    stretched with it, and points part from the float64 walk by up to hundreds
    of units. Where the walk stretches little, they do not: the drift is float32's,
    not the kernel's."""
    op = op_of(case)
    x, y = probe_points(op, *circles(op))
    kx, ky, _ = run_op(renderer, op, x, y, None, 4)
    x, y = x.astype(np.float64), y.astype(np.float64)
    rx, ry = STROKE.inverse(op.values, x, y)
    err = np.hypot(kx - rx, ky - ry)
    stretch = _stretch(lambda a, b: STROKE.inverse(op.values, a, b), x, y)
    assert err.max() > 1  # the case reaches the limit this test is about
    assert err[stretch <= 10].max() <= 5e-3
    assert stretch[err > 0.05].min() >= 100
    assert stretch[err > 1].min() >= 1000
    assert (err / stretch).max() <= 0.05  # what a twentieth of a unit there becomes


def test_at_full_drag_pictures_agree_where_the_walk_stretches_little(renderer):
    """Three strokes at their own drag over a texture: where the walk stretches
    the plane at most tenfold at a pixel's centre, the kernel's picture agrees with
    the reference's as everywhere else in the suite; the rest (half of the
    picture here) samples the texture ten or more units apart within one pixel."""
    ops = [{"type": "stroke", **CASES[c][0]} for c in ("zigzag", "loop", "timed")]
    recipe = parse_recipe({"canvas": CANVAS, "antialias": "rgss", "ops": ops}, "blocks.json")
    spec, geom = recipe.at(1.23), geometry(recipe.canvas, tuple(CANVAS), (64, 48))
    yy, xx = np.mgrid[0:48, 0:64]
    image = np.stack([xx * 4, yy * 5, (xx ^ yy) * 8 % 256], axis=-1).astype(np.uint8)
    ours, ref = renderer.render(spec, geom, image)[..., :3], reference_render(spec, geom, image)

    def inverse(x, y):
        for op in reversed(spec.ops):
            x, y = STROKE.inverse(op.values, x, y)
        return x, y

    cy, cx = np.mgrid[0 : CANVAS[1], 0 : CANVAS[0]] + 0.5  # pixel centres, 1 unit a pixel
    calm = _stretch(inverse, cx.astype(np.float64), cy.astype(np.float64)) <= 10
    assert 0.3 < calm.mean() < 0.9
    assert agreement(ours[calm][None], ref[calm][None]) >= KERNEL_SHARE
    assert agreement(ours, ref) < KERNEL_SHARE  # the whole picture does not
