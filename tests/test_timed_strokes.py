"""Format 1, revision 4: a ``stroke`` with ``times`` (a gesture replayed as it was
drawn) and ``heal`` on every op. The stylus' travel s(t) follows the gesture;
the steps lie at the fixed spacing w/4 (whole ones, then the one partial step to
the stylus), so a stroke growing point by point renders exactly as the finished
one at the time of its newest point; the maps stay exact inverses that preserve
area; the kernel walks a point where the reference does; every op heals back to
the input; a still's default time counts ``times`` but not ``heal``; bad timings
are refused through the CLI in one line with their JSON path (exit 2)."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
from helpers import assert_refused
from op_probe import run_op
from tolerances import KERNEL_SHARE, SVG_SHARE

from marblevideo.opencl.program import STILL_CODE, pack_params
from marblevideo.opencl.selfcheck import agreement
from marblevideo.ops import LAYOUTS, REGISTRY, op_def
from marblevideo.ops.stroke import acting_steps, layout
from marblevideo.ops.stylus import arc_lengths, travel
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import OpState, geometry
from marblevideo.reference import jacobian
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

STROKE = op_def("stroke")
#: A drawn S (a repeated point where the hand paused, a first segment shorter than
#: a step), with a comb of three styluses; times as a hand gives them (a pause).
POINTS = [[30, 60], [33, 61], [70, 40], [120, 50], [120, 50], [150, 110], [110, 160],
          [160, 190], [230, 150]]  # fmt: skip
TIMES = [0.0, 0.05, 0.4, 0.8, 1.1, 1.5, 1.9, 2.3, 2.9]
#: A gentle drag: where a self-crossing comb folds the ink tightly, float32 walks
#: drift from float64 ones (revision-3 strokes alike), beyond what SECTION_PX bounds.
GESTURE = {"type": "stroke", "points": POINTS, "times": TIMES, "width": 20, "drag": 0.7,
           "tines": [-12, 0, 12]}  # fmt: skip
DROPS = [
    {"type": "drop", "center": [120 + 40 * (k % 3), 80 + 45 * (k // 3)], "radius": 34,
     "color": c}
    for k, c in enumerate(("#1d3557", "#e9c46a", "#b23a48", "#2a9d8f", "#f4a261", "#264653"))
]  # fmt: skip
CANVAS = [260, 220]
#: Moments: before the gesture, inside its first step (s < d), mid-gesture (a whole
#: number of points and between two), after it, mid-heal, healed.
MOMENTS = {"first-step": 0.03, "mid": 1.3, "between": 2.05, "after": 3.0, "mid-heal": 4.6}
#: A kernel point against the float64 inverse of the same float32 point, in canvas units.
SECTION_PX = 2e-3


def doc(stroke: dict | None = None, **more) -> dict:
    return {
        "canvas": CANVAS,
        "background": "#f6efe0",
        "ops": [*DROPS, {**GESTURE, **(stroke or {}), **more}],
    }


def values_at(t: float, **more) -> dict:
    return parse_recipe(doc(heal=[4, 5.5], **more)).at(t).ops[-1].values


def grid(step: float = 1.9):
    y, x = np.mgrid[-10:230:step, -10:270:step]
    return x.ravel() + 0.013, y.ravel() + 0.007


# ---------------------------------------------------------------------------- the stylus


def test_the_stylus_travels_the_gesture():
    arc = arc_lengths([c for p in POINTS for c in p])
    assert arc[4] == arc[3]  # the repeated point adds 0
    assert travel(TIMES, arc, -1.0) == 0.0 and travel(TIMES, arc, 9.0) == arc[-1]
    for i, t in enumerate(TIMES[:-1]):
        assert travel(TIMES, arc, t) == arc[i] if TIMES[i + 1] > t else True
    half = (TIMES[2] + TIMES[3]) / 2
    assert travel(TIMES, arc, half) == pytest.approx((arc[2] + arc[3]) / 2, abs=1e-12)
    assert travel(TIMES, arc, 1.0) == arc[3] == arc[4]  # the pause: the stylus rests


def test_steps_lie_at_a_quarter_width_whole_then_one_partial():
    v = values_at(MOMENTS["mid"])
    centres, halves, turns = acting_steps(v)
    s = v["stylus"]
    d = v["width"] / 4
    whole = int(s // d)
    assert len(centres) == 3 * (whole + 1) and s > whole * d  # whole steps, then the partial
    theta = v["drag"] * d * 16 / (9 * v["width"])
    assert np.allclose(turns[:-3], theta, rtol=0, atol=1e-15)
    assert 0 < turns[-1] < theta  # the partial step turns by its own length
    assert np.allclose(np.hypot(*halves.T), v["width"] / 2)
    healed = values_at(4.0 + 0.75 * 1.5)  # h = 1/4: the stylus a quarter of the way
    assert healed["stylus"] * healed["travel"] == pytest.approx(0.25 * healed["stylus"])


@pytest.mark.parametrize("moment", list(MOMENTS))
def test_forward_then_inverse_returns_mid_gesture(moment):
    v = values_at(MOMENTS[moment])
    x, y = grid()
    fx, fy = STROKE.forward(v, x, y)
    assert np.hypot(fx - x, fy - y).max() > 0.2  # it moves something
    bx, by = STROKE.inverse(v, fx, fy)
    assert np.hypot(bx - x, by - y).max() <= 1e-6


@pytest.mark.parametrize("moment", ["first-step", "mid", "between"])
def test_the_jacobian_determinant_is_one_mid_gesture(moment):
    """Area preserving mid-gesture, by central differences (points stretched over
    10-fold left out: there the differences' truncation error, which falls as
    h^2, reaches 1e-5 at h = 1e-7 where the comb folds the ink tightly)."""
    x, y = grid(2.3)
    v = values_at(MOMENTS[moment])
    fx, fy = STROKE.forward(v, x, y)
    moved = np.hypot(fx - x, fy - y) > 1e-3
    j = jacobian(OpState("stroke", v), x[moved], y[moved], h=1e-7)
    tame = np.abs(j).max(axis=(1, 2)) < 10
    assert moved.sum() > 50 and tame.mean() > 0.9
    assert np.abs(np.linalg.det(j[tame]) - 1).max() <= 1e-6


def test_revision_3_tines_follow_the_first_steps_normal():
    """N0 of a revision-3 stroke is the normal of Q_0 -> Q_1, not of the first
    given segment (here a few units long and at 18 degrees to the first step)."""
    flat = tuple(float(c) for p in POINTS for c in p)
    lay = layout(flat, 20.0, (-9.0, 0.0, 9.0))
    q0 = np.array(POINTS[0], float)
    u = (lay.centres[1] - q0) / np.hypot(*(lay.centres[1] - q0))  # C_0 lies on Q_0 -> Q_1
    normal = np.array([-u[1], u[0]])
    assert np.allclose(lay.centres[2] - lay.centres[1], 9 * normal, atol=1e-9)
    assert np.allclose(lay.halves[0], 10 * normal, atol=1e-9)


# ---------------------------------------------------------------------------- growing


def _truncated(i: int) -> dict:
    """The gesture as drawn up to point i (its points and times so far)."""
    return {"points": POINTS[: i + 1], "times": TIMES[: i + 1]}


@pytest.mark.parametrize("i", [1, 2, 3, 4, 6, 8])
def test_a_growing_stroke_is_the_finished_stroke_at_its_newest_point(renderer, i):
    t = TIMES[i]
    finished = parse_recipe(doc()).at(t)
    growing = parse_recipe(doc(_truncated(i))).at(t)
    x, y = grid(1.3)
    fin = STROKE.inverse(finished.ops[-1].values, x, y)
    grow = STROKE.inverse(growing.ops[-1].values, x, y)
    assert np.array_equal(fin[0], grow[0]) and np.array_equal(fin[1], grow[1])
    assert pack_params(finished).key == pack_params(growing).key  # the kernel's data
    geom = geometry(CANVAS, (130, 110))
    assert np.array_equal(renderer.render(finished, geom), renderer.render(growing, geom))
    assert np.array_equal(reference_render(finished, geom), reference_render(growing, geom))


# ---------------------------------------------------------------------------- the device


@pytest.mark.parametrize("moment", list(MOMENTS))
@pytest.mark.parametrize("lanes", [None, 1], ids=["vectors", "one-pixel"])
def test_the_kernel_section_is_the_float64_inverse(renderer, one_pixel_renderer, moment, lanes):
    device = renderer if lanes is None else one_pixel_renderer
    op = OpState("stroke", values_at(MOMENTS[moment]))
    rng = np.random.default_rng(7)
    x = rng.uniform(-10, 270, 8192).astype(np.float32)
    y = rng.uniform(-10, 230, 8192).astype(np.float32)
    kx, ky, _ = run_op(device, op, x, y)
    rx, ry = STROKE.inverse(op.values, x.astype(np.float64), y.astype(np.float64))
    err = np.hypot(kx - rx, ky - ry)
    assert (err <= SECTION_PX).mean() >= 0.999, err.max()
    assert (np.hypot(rx - x, ry - y) > 0.2).mean() > 0.01
    still = (rx == x) & (ry == y)
    assert np.array_equal(kx[still], x[still]) and np.array_equal(ky[still], y[still])


@pytest.mark.parametrize("moment", list(MOMENTS))
def test_a_gesture_renders_on_the_device_as_in_the_reference(renderer, moment):
    recipe = parse_recipe(doc(heal=[4, 5.5]))
    spec = recipe.at(MOMENTS[moment])
    geom = geometry(CANVAS, (130, 110))
    share = agreement(renderer.render(spec, geom), reference_render(spec, geom))
    assert share >= KERNEL_SHARE, share


def test_the_lattice_path_of_a_gesture_over_an_input(renderer):
    """An op with ``heal`` or a stroke with ``times`` is animated: a video frame
    interpolates from the lattice, within the kernel's agreement."""
    from marblevideo.marbler import Marbler, image_size

    image = np.zeros((110, 130, 4), np.uint8)
    image[..., 0] = np.arange(130)[None, :] * 2
    image[..., 1] = np.arange(110)[:, None] * 2
    image[..., 3] = 255
    for recipe in (
        parse_recipe({"canvas": CANVAS, "ops": [GESTURE]}),
        parse_recipe({"canvas": CANVAS, "ops": [{**DROPS[0], "heal": [1, 2]}]}),
    ):
        assert recipe.is_animated
    recipe = parse_recipe({"canvas": CANVAS, "ops": [{**GESTURE, "heal": [4, 5]}]})
    marbler = Marbler(recipe, renderer)
    for t in (1.3, 4.5):
        got = marbler.render(image, t, animated=True)
        spec, geom = marbler.frame_at(image_size(image), t, None, None)
        assert agreement(got, reference_render(spec, geom, image)) >= KERNEL_SHARE


# ---------------------------------------------------------------------------- healing


def _every_op_healing() -> dict:
    """Every registered op's example (and a layout) healing over [1, 2]."""
    ops = [{**copy.deepcopy(d.example), "heal": [1, 2]} for d in REGISTRY.values()]
    ops.append({**GESTURE, "heal": [0.5, 2]})
    ops.append({**copy.deepcopy(LAYOUTS["rings"].example), "heal": [1, 1]})
    return {"canvas": [80, 60], "antialias": "none", "ops": ops}


def test_a_healed_recipe_renders_as_the_input_exactly(renderer):
    recipe = parse_recipe(_every_op_healing())
    assert {op.type for op in recipe.ops} >= set(REGISTRY)
    rng = np.random.default_rng(3)
    image = rng.integers(0, 256, (60, 80, 4), dtype=np.uint8)
    image[..., 3] = 255
    healing = recipe.at(1.5)
    assert not all(pack_params(healing).params.reshape(len(recipe.ops), -1)[:, -1] == STILL_CODE)
    geom = geometry((80, 60), (80, 60), (80, 60))
    assert not np.array_equal(renderer.render(healing, geom, image), image)
    for t in (2.0, 7.0):
        healed = recipe.at(t)
        assert (pack_params(healed).params.reshape(len(recipe.ops), -1)[:, -1] == STILL_CODE).all()
        assert np.array_equal(renderer.render(healed, geom, image), image)
        assert np.array_equal(reference_render(healed, geom, image), image)


def test_healing_scales_each_ops_progress():
    recipe = parse_recipe(
        {
            "canvas": CANVAS,
            "ops": [
                {**DROPS[0], "start": 0, "end": 2, "heal": [3, 5]},
                {"type": "vortex", "center": [50, 50], "alpha": 40, "lambda": 8, "heal": [-3, -1]},
            ],
        }  # fmt: skip
    )
    radius = [recipe.at(t).ops[0]["radius"] for t in (1.0, 2.5, 4.0, 5.0)]
    assert radius == pytest.approx([34 * 0.5**0.5, 34, 34 * 0.5**0.5, 0])
    assert recipe.at(-2).ops[1]["alpha"] == pytest.approx(20) and recipe.at(0).ops[1]["alpha"] == 0


# ---------------------------------------------------------------------------- time and files


def test_a_stills_default_time_counts_times_but_not_heal(cli, tmp_path):
    keyed = {"type": "vortex", "center": [40, 40], "lambda": 9,
             "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 2.5, "v": 30}]}}  # fmt: skip
    recipe = parse_recipe({**doc(heal=[6, 7]), "ops": [keyed, *doc(heal=[6, 7])["ops"]]})
    assert recipe.end_time() == TIMES[-1]
    (tmp_path / "g.json").write_text(json.dumps(doc(heal=[6, 7])))
    for args in ((), ("--time", str(TIMES[-1])), ("--time", "1.3")):
        name = f"g{len(args)}{args[-1] if args else ''}.png"
        proc = cli("--ops", "g.json", "-o", name, "--size", "130x110", *args)
        assert proc.returncode == 0, proc.stderr
    default, finished = (tmp_path / "g0.png").read_bytes(), (tmp_path / "g22.9.png").read_bytes()
    assert default == finished and default != (tmp_path / "g21.3.png").read_bytes()


def test_a_still_after_a_heal_is_noted_with_the_time_of_strongest_motion():
    from marblevideo.reference.motion import rest_note

    healed = parse_recipe({"canvas": CANVAS, "ops": [{**GESTURE, "heal": [2.0, 2.5]}]})
    note = rest_note(healed, None)
    assert note is not None and "come back near rest" in note
    later = parse_recipe({"canvas": CANVAS, "ops": [{**GESTURE, "heal": [4, 5]}]})
    assert rest_note(later, None) is None  # it heals after the still


def test_svg_of_a_timed_stroke_is_the_finished_stroke(cli, tmp_path, renderer):
    from svg_raster import agreement as svg_agreement
    from svg_raster import rasterize

    (tmp_path / "g.json").write_text(json.dumps(doc(heal=[6, 7])))
    runs = {"g.svg": (), "f.svg": ("--time", str(TIMES[-1])), "m.svg": ("--time", "1.3")}
    for out, args in runs.items():
        proc = cli("--ops", "g.json", "-o", out, "--size", "130x110", *args)
        assert proc.returncode == 0, proc.stderr
    svg = (tmp_path / "g.svg").read_text()
    assert svg == (tmp_path / "f.svg").read_text() != (tmp_path / "m.svg").read_text()
    recipe = parse_recipe(doc(heal=[6, 7]))
    raster = renderer.render(recipe.at(TIMES[-1]), geometry(CANVAS, (130, 110)))
    assert svg_agreement(rasterize(svg, (130, 110)), raster) >= SVG_SHARE


REFUSALS = {
    "times-count": ({"times": TIMES[:-1]}, "ops[6].times", "one time per point (9), got 8"),
    "times-decrease": (
        {"times": [*TIMES[:3], 0.3, *TIMES[4:]]},
        "ops[6].times[3]",
        "must not decrease: got 0.3 after 0.4",
    ),
    "times-nan": ({"times": [*TIMES[:2], "NaN", *TIMES[3:]]}, "ops[6].times[2]", ""),
    "times-start": ({"start": 0}, "ops[6].times", "neither `start` nor `end`"),
    "times-end": ({"start": 0, "end": 2}, "ops[6].times", "neither `start` nor `end`"),
    "heal-order": ({"heal": [3, 1]}, "ops[6].heal", "t0 <= t1, got [3, 1]"),
    "heal-negative": ({"heal": [-1, -3]}, "ops[6].heal", "t0 <= t1, got [-1, -3]"),
    "heal-one": ({"heal": [1]}, "ops[6].heal", ""),
    "heal-text": ({"heal": ["a", 2]}, "ops[6].heal[0]", ""),
}


def test_refusals_exit_2_in_one_line_with_their_path(cli, tmp_path):
    for name, (change, path, expected) in REFUSALS.items():
        text = json.dumps(doc(change)).replace('"NaN"', "NaN")
        assert_refused(cli, tmp_path, text, path, expected, name)
    (tmp_path / "r.json").write_text(json.dumps(doc(heal=[-3, -1])))
    proc = cli("--ops", "r.json", "-o", "out.png", "--size", "26x22")
    assert proc.returncode == 0, proc.stderr


def test_a_layouts_heal_reaches_its_drops():
    layout_op = {**LAYOUTS["rings"].example, "heal": [1, 3]}
    recipe = parse_recipe({"canvas": [80, 60], "ops": [layout_op]})
    assert len(recipe.ops) == layout_op["count"]
    assert [op.heal for op in recipe.ops] == [(1.0, 3.0)] * layout_op["count"]


def test_ops_command_and_schema_describe_times_and_heal(cli):
    proc = cli("ops", "stroke")
    assert proc.returncode == 0, proc.stderr
    text = " ".join(proc.stdout.split())
    assert "times [seconds]" in text and "heal [t0, t1] seconds" in text
    assert "with times, the stylus is where the gesture was" in text
    proc = cli("schema")
    schema = json.loads(proc.stdout)
    assert schema["$defs"]["stroke"]["properties"]["times"]["$ref"] == "#/$defs/timeList"
    assert all("heal" in schema["$defs"][t]["properties"] for t in ("drop", "stroke", "rings"))


def test_a_video_of_a_sheet_runs_until_the_last_op_has_healed(cli, tmp_path):
    recipe = parse_recipe(doc(heal=[3.2, 3.6]))
    assert recipe.end_time() == TIMES[-1] and recipe.settled_time() == 3.6
    (tmp_path / "g.json").write_text(json.dumps(doc(heal=[3.2, 3.6])))
    proc = cli("--ops", "g.json", "-o", "g.mp4", "--size", "64x54", "--fps", "10")
    assert proc.returncode == 0, proc.stderr
    assert "46 frames, 4.60 s" in proc.stderr
