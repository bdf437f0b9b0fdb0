"""The free-hand ``stroke`` (format 1 revision 3): its float64 maps are
exact inverses that preserve area and move nothing beyond ``width`` of the path,
the kernel walks a point where the reference does (vectors and one pixel), the
stylus travels with progress, static strokes are laid out once, and bad strokes
are refused through the CLI in one line with their JSON path (exit 2)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import assert_refused
from op_probe import run_op
from tolerances import KERNEL_SHARE, SVG_SHARE

from marblevideo.opencl.program import STILL_CODE, pack_params
from marblevideo.opencl.selfcheck import agreement
from marblevideo.ops import op_def
from marblevideo.ops.stepblocks import BLOCK_FLOATS, BLOCK_STEPS
from marblevideo.ops.stroke import STEP_FLOATS, _rows, angles, layout
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import OpState, geometry
from marblevideo.reference import jacobian
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

STROKE = op_def("stroke")
#: A curved stroke, a comb along an S and a tulip's stroke up through its drops.
CASES = {
    "curve": {"points": [[20, 150], [80, 60], [160, 40], [230, 110]], "width": 30, "drag": 1.2},
    "comb": {
        "points": [[30, 40], [120, 70], [60, 120], [150, 160], [240, 130]],
        "width": 14,
        "drag": -0.8,
        "tines": [-24, 0, 24],
    },
    "tulip": {"points": [[160, 235], [160, 60]], "width": 36, "drag": 1.6},
}
IDS = list(CASES)
#: A kernel point against the float64 inverse of the same float32 point, in canvas units.
SECTION_PX = 2e-3


def values(case: str, travel: float = 1.0) -> dict:
    op = parse_recipe({"canvas": [260, 200], "ops": [{"type": "stroke", **CASES[case]}]})
    return {**op.at(0).ops[0].values, "travel": travel}


def grid(step: float = 1.7):
    y, x = np.mgrid[-20:220:step, -20:280:step]
    return x.ravel() + 0.013, y.ravel() + 0.007


@pytest.mark.parametrize("case", IDS)
@pytest.mark.parametrize("travel", [1.0, 0.37])
def test_forward_then_inverse_returns_within_a_millionth_of_a_pixel(case, travel):
    v = values(case, travel)
    x, y = grid()
    fx, fy = STROKE.forward(v, x, y)
    assert np.hypot(fx - x, fy - y).max() > 1.0  # it moves something
    bx, by = STROKE.inverse(v, fx, fy)
    assert np.hypot(bx - x, by - y).max() <= 1e-6


@pytest.mark.parametrize("case", IDS)
def test_the_jacobian_determinant_is_one(case):
    """Area preserving: det J = 1 +- 1e-6 by central differences, on points the
    stroke moves (those it stretches over 30-fold are left out: differences of
    1e-4 units cannot resolve them)."""
    x, y = grid(2.3)
    v = values(case)
    fx, fy = STROKE.forward(v, x, y)
    moved = np.hypot(fx - x, fy - y) > 1e-3
    op = OpState("stroke", v)
    j = jacobian(op, x[moved], y[moved], h=1e-7)
    tame = np.abs(j).max(axis=(1, 2)) < 30
    assert tame.mean() > 0.95
    det = np.linalg.det(j[tame])
    assert np.abs(det - 1).max() <= 1e-6, np.abs(det - 1).max()


@pytest.mark.parametrize("case", IDS)
def test_nothing_farther_than_width_from_the_steps_moves(case):
    v = values(case, 0.6)
    lay = layout(tuple(v["points"]), v["width"], tuple(v["tines"]))
    acting = int(np.count_nonzero(angles(v, lay)))  # a prefix: e_k > 0 for k < p n
    ends = np.concatenate([lay.centres + lay.halves, lay.centres - lay.halves])
    ends = np.concatenate([ends[:acting], ends[len(lay.centres) : len(lay.centres) + acting]])
    x, y = grid(1.1)
    near = np.hypot(x[:, None] - ends[:, 0], y[:, None] - ends[:, 1]).min(axis=1)
    far = near >= v["width"]
    fx, fy = STROKE.forward(v, x, y)
    ix, iy = STROKE.inverse(v, x, y)
    assert far.mean() > 0.3 and (~far).mean() > 0.1
    assert np.array_equal(fx[far], x[far]) and np.array_equal(fy[far], y[far])
    assert np.array_equal(ix[far], x[far]) and np.array_equal(iy[far], y[far])
    # and so nothing moves farther than 3/2 width from the (comb's translated) path
    assert (np.hypot(fx - x, fy - y)[near >= v["width"]] == 0).all()


@pytest.mark.parametrize("case", IDS)
@pytest.mark.parametrize("lanes", [None, 1], ids=["vectors", "one-pixel"])
@pytest.mark.parametrize("travel", [1.0, 0.5])
def test_the_kernel_section_is_the_float64_inverse(
    renderer, one_pixel_renderer, case, lanes, travel
):
    device = renderer if lanes is None else one_pixel_renderer
    op = OpState("stroke", values(case, travel))
    rng = np.random.default_rng(len(case))
    x = rng.uniform(-20, 280, 8192).astype(np.float32)
    y = rng.uniform(-20, 220, 8192).astype(np.float32)
    kx, ky, ink = run_op(device, op, x, y)
    rx, ry = STROKE.inverse(op.values, x.astype(np.float64), y.astype(np.float64))
    assert (ink < 0).all()
    err = np.hypot(kx - rx, ky - ry)
    assert (err <= SECTION_PX).mean() >= 0.999, err.max()
    assert (np.hypot(rx - x, ry - y) > 1).mean() > 0.05  # the points were moved
    still = (rx == x) & (ry == y)  # beyond every step's reach: kept exactly on the device too
    assert still.mean() > 0.3 and np.array_equal(kx[still], x[still])
    assert np.array_equal(ky[still], y[still])


def _tulip(**more) -> dict:
    drops = [
        {"type": "drop", "center": [160, 150], "radius": r, "color": c}
        for r, c in ((60, "#b0172e"), (45, "#f4d35e"), (32, "#b0172e"), (20, "#f4d35e"))
    ]
    stroke = {"type": "stroke", **CASES["tulip"], **more}
    return {"canvas": [320, 400], "background": "#f6efe0", "ops": [*drops, stroke]}


@pytest.mark.parametrize("t", [0.3, 1.0, 2.0])
def test_the_stylus_travels_on_the_device_as_in_the_reference(renderer, t):
    """Start 0, end 2: over a picture at three times, unrolled walk."""
    recipe = parse_recipe(_tulip(start=0, end=2), "tulip.json")
    spec = recipe.at(t)
    geom = geometry(recipe.canvas, (160, 200))
    share = agreement(renderer.render(spec, geom), reference_render(spec, geom))
    assert share >= KERNEL_SHARE, (t, share)


def test_progress_packs_the_steps_the_stylus_has_passed():
    recipe = parse_recipe(_tulip(start=1, end=3), "tulip.json")
    n = layout(tuple(recipe.at(3).ops[-1]["points"]), 36.0, (0.0,)).n
    counts = []
    for t in (0.5, 1.0, 1.5, 2.9, 3.0):
        row = pack_params(recipe.at(t)).params.reshape(-1, 12)[-1]
        counts.append(int(row[1]) if row[-1] != STILL_CODE else None)
    assert counts[:2] == [None, None]  # before and at its start: still, skipped
    assert counts[2:] == [int(np.ceil(0.25 * n)), int(np.ceil(0.95 * n)), n]
    packed = pack_params(recipe.at(3))
    at = int(packed.params.reshape(-1, 12)[-1][0])
    blocks = -(-n // BLOCK_STEPS)  # the steps, then their blocks' culling circles
    assert packed.lists.size == at + n * STEP_FLOATS + blocks * BLOCK_FLOATS


def test_a_static_stroke_is_laid_out_once():
    recipe = parse_recipe(_tulip(), "tulip.json")
    layout.cache_clear()
    _rows.cache_clear()
    first = pack_params(recipe.at(0))
    for t in (0.1, 0.2, 5.0):
        again = pack_params(recipe.at(t))
        assert again.key == first.key
    assert layout.cache_info().misses == 1 and _rows.cache_info().misses == 1


def test_a_keyed_drag_between_keys_and_the_settled_value():
    doc = _tulip(drag={"keys": [{"t": 0, "v": 0, "ease": [0.5, 3, 0.5, 3]}, {"t": 1, "v": 4}]})
    recipe = parse_recipe(doc, "tulip.json")
    assert recipe.at(0).ops[-1]["drag"] == 0
    assert STROKE.still(recipe.at(0).ops[-1].values)
    assert recipe.at(0.5).ops[-1]["drag"] == 4.0  # the overshooting ease is held to 4
    assert recipe.at(1).ops[-1]["drag"] == 4.0


def test_the_uv_pass_shows_what_the_device_renders(renderer):
    from helpers import identity_pass

    from marblevideo.outputs.uv import render_uv

    recipe = parse_recipe(_tulip(), "tulip.json")
    spec = recipe.at(0)
    w, h = 160, 200
    u, v = identity_pass(w, h)
    got = render_uv(spec, u, v, np.ones((h, w), bool))
    assert agreement(got, renderer.render(spec, geometry(recipe.canvas, (w, h)))) >= KERNEL_SHARE


# ---------------------------------------------------------------------------- refusals

LONG = [[0, 0], [3000, 0], [3000, 3000], [0, 3000], [0, 6000], [3000, 6000]]
REFUSALS = {
    "one-point": ({"points": [[5, 5]]}, "ops[4].points", "list of 2..4096 points"),
    "no-distinct": ({"points": [[5, 5], [5, 5], [5, 5]]}, "ops[4].points", "2 distinct points"),
    "width-0": ({"width": 0}, "ops[4].width", "> 0"),
    "drag-5": ({"drag": 5}, "ops[4].drag", "-4..4, got 5"),
    "drag-key": (
        {"drag": {"keys": [{"t": 0, "v": 1}, {"t": 1, "v": -4.5}]}},
        "ops[4].drag.keys[1].v",
        "-4..4, got -4.5",
    ),
    "points-4097": (
        {"points": [[k % 7, k // 7] for k in range(4097)]},
        "ops[4].points",
        "2..4096",
    ),
    "tines-65": ({"tines": list(range(65))}, "ops[4].tines", "at most 64 tines, got 65"),
    "steps": (
        {"points": LONG, "width": 0.5, "tines": [0, 1]},
        "ops[4]",
        "a stroke of 240000 steps",
    ),
}


def test_refusals_exit_2_in_one_line_with_their_path(cli, tmp_path):
    for name, (change, path, expected) in REFUSALS.items():
        assert_refused(cli, tmp_path, json.dumps(_tulip(**change)), path, expected, name)


# ---------------------------------------------------------------------------- surfaces


def test_ops_command_describes_the_stroke(cli):
    proc = cli("ops", "stroke")
    assert proc.returncode == 0, proc.stderr
    text = " ".join(proc.stdout.split())
    assert "points [[x, y], ...] required" in text and "width number > 0 = 24" in text
    assert "the stylus travels the path" in text and "drag" in text


def test_svg_and_pdf_of_a_stroke_design(cli, tmp_path, renderer):
    from svg_raster import agreement as svg_agreement
    from svg_raster import rasterize

    (tmp_path / "t.json").write_text(json.dumps(_tulip()))
    for out in ("t.svg", "t.pdf"):
        proc = cli("--ops", "t.json", "-o", out, "--size", "160x200")
        assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "t.pdf").read_bytes().startswith(b"%PDF")
    recipe = parse_recipe(_tulip(), "t.json")
    raster = renderer.render(recipe.at(0), geometry(recipe.canvas, (160, 200)))
    svg = (tmp_path / "t.svg").read_text()
    assert svg_agreement(rasterize(svg, (160, 200)), raster) >= SVG_SHARE


# ---------------------------------------------------------------------------- presets

STROKE_PRESETS = ("tulip", "heart", "french-curl", "bird", "gesture")


@pytest.mark.parametrize("name", STROKE_PRESETS)
def test_a_stroke_preset_renders_on_the_device_as_the_reference_does(renderer, name):
    from marblevideo import load_recipe

    recipe = load_recipe(name)
    assert any(op.type == "stroke" for op in recipe.ops) and recipe.canvas is not None
    for t in (recipe.end_time() * 0.8, recipe.end_time()):
        spec = recipe.at(t)
        geom = geometry(recipe.canvas, (120, 100))
        share = agreement(renderer.render(spec, geom), reference_render(spec, geom))
        assert share >= KERNEL_SHARE, (name, t, share)


def test_the_stroke_presets_are_what_their_script_writes(cli, tmp_path):
    import importlib.util

    from helpers import ROOT

    path = ROOT / "samples" / "make_stroke_presets.py"
    spec = importlib.util.spec_from_file_location("make_stroke_presets", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.HERE = tmp_path
    module.main()
    for name in STROKE_PRESETS:
        written = (tmp_path / f"{name}.json").read_text()
        assert written == (ROOT / "samples" / f"{name}.json").read_text(), name
        proc = cli("presets", name)
        assert proc.returncode == 0 and json.loads(proc.stdout) == json.loads(written)


def test_the_readme_states_the_stroke_limits():
    from helpers import ROOT

    from marblevideo.ops.stroke import MAX_POINTS, MAX_STEPS, MAX_TINES

    readme = (ROOT / "README.md").read_text()
    row = next(line for line in readme.splitlines() if line.startswith("| a `stroke` |"))
    for value in (f"{MAX_POINTS:,}", f"1..{MAX_TINES} tines", f"{MAX_STEPS:,} steps"):
        assert value in row, value
