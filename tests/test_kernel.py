"""The OpenCL kernel against the NumPy reference, on seeded random recipes."""

from __future__ import annotations

import threading

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


def check(renderer, recipe_dict, size, image=None, t=None):
    recipe = parse_recipe(recipe_dict, "random.json")
    t = recipe.end_time() if t is None else t
    spec = recipe.at(t)
    input_size = None if image is None else (image.shape[1], image.shape[0])
    geom = geometry(recipe.canvas, size, input_size)
    ours = renderer.render(spec, geom, image)
    ref = reference_render(spec, geom, image)
    assert ours.shape == ref.shape == (size[1], size[0], 4)
    share = agreement(ours, ref)
    assert share >= KERNEL_SHARE, f"only {share:.4f} of pixels agree (t={t})"
    return ours, ref


@pytest.mark.parametrize("seed", range(24))  # 24 = every AA pattern x every edges mode
def test_kernel_matches_reference_on_input(renderer, seed):
    recipe = random_recipe(seed)
    assert recipe["antialias"] == PATTERNS[seed % 6] and recipe["edges"] == EDGES[seed // 6 % 4]
    image = make_image(96 + seed % 5, 72 + seed % 3, seed, alpha=seed % 2 == 0)
    for t in (0.0, 0.7, 1.9, 10.0):  # before, during and after the keys and progress
        check(renderer, recipe, (113, 89), image, t)


@pytest.mark.parametrize("seed", range(100, 112))
def test_kernel_matches_reference_on_blank_sheet(renderer, seed):
    recipe = random_recipe(seed, 200, 140, blank=True)
    for t in (0.5, 10.0):
        check(renderer, recipe, (150, 107), None, t)


def gentle(recipe: dict) -> dict:
    """``recipe`` with its ops' alpha and amplitude (constants) at a fifth, so that a
    recipe of many ops keeps a picture comparable with the reference's."""
    for op in recipe["ops"]:
        for key in ("alpha", "amplitude"):
            if isinstance(op.get(key), float):
                op[key] *= 0.2
    return recipe


def test_long_recipe_uses_loop_walk_and_matches(renderer):
    from marblevideo.opencl.program import UNROLL_LIMIT

    recipe = gentle(random_recipe(7, n_ops=UNROLL_LIMIT + 13))
    check(renderer, recipe, (90, 70), make_image(80, 60, 3))


def test_the_loop_walk_serves_every_recipe_with_one_program():
    """Renderer(loop_walk=True), as the designer uses: recipes of other ops, other
    counts (none included) and the long one all match the reference, built once."""
    from marblevideo.opencl.program import UNROLL_LIMIT

    renderer = fresh_renderer(loop_walk=True)  # fresh: counts the programs it builds
    image = make_image(80, 60, 3)
    fixed = {"antialias": "rgss", "edges": "clamp"}
    for seed, n_ops in ((1, None), (2, 3), (3, 1), (4, 0), (7, UNROLL_LIMIT + 2)):
        check(renderer, gentle(random_recipe(seed, n_ops=n_ops) | fixed), (90, 70), image)
    assert renderer.programs.built == 1


def test_identity_recipe_returns_the_input_exactly(renderer):
    image = make_image(67, 41, 5, alpha=True)
    recipe = {"marblevideo": 1, "antialias": "none", "ops": []}
    ours, _ = check(renderer, recipe | {"canvas": [67, 41]}, (67, 41), image)
    assert np.array_equal(ours, image)


def test_a_prebuilt_program_is_built_once_and_renders_as_ever():
    """prebuild builds in a thread; a render asking meanwhile waits for that build
    instead of starting its own, and the result matches the reference."""
    from marblevideo.opencl.program import Structure

    renderer = fresh_renderer()  # fresh: nothing built yet, its build is watched
    builds = []
    build = renderer.programs.build
    renderer.programs.build = lambda st: (
        builds.append((st, threading.current_thread().name)) or build(st)
    )
    recipe = parse_recipe(random_recipe(3), "random.json")
    structure = Structure.of(recipe, True)
    renderer.prebuild(structure)
    check(renderer, random_recipe(3), (97, 61), make_image(80, 60, 3))
    assert builds == [(structure, "marblevideo-build")]
    assert renderer.kernel_for(structure) is renderer.kernel_for(structure)


@pytest.mark.parametrize("seed", [0, 5, 14, 23])
def test_adaptive_over_an_input_matches_reference(seed):
    check(fresh_renderer(adaptive=True), random_recipe(seed), (101, 77), make_image(90, 66, seed))


@pytest.mark.parametrize("lanes", [1, 4, 8])
def test_every_lane_width_agrees(lanes):
    narrow = fresh_renderer(lanes=lanes, chains=1 if lanes == 1 else 2)
    check(narrow, random_recipe(3), (61, 47), make_image(50, 40, 1))
    check(narrow, random_recipe(4, blank=True), (61, 47))


def test_parameter_change_does_not_rebuild(renderer):
    recipe = parse_recipe(random_recipe(11), "r.json")
    geom = geometry(recipe.canvas, (64, 48), (64, 48))
    image = make_image(64, 48)
    renderer.render(recipe.at(0.0), geom, image)
    built = renderer.programs.built
    frames = [renderer.render(recipe.at(t), geom, image) for t in np.linspace(0, 3, 7)]
    assert renderer.programs.built == built
    assert any(not np.array_equal(frames[0], f) for f in frames[1:])


@pytest.fixture(scope="module")
def full_pattern():
    return fresh_renderer(adaptive=False)


@pytest.mark.parametrize("seed", [1, 8, 13, 101])
def test_full_pattern_path_matches_reference(full_pattern, seed):
    image = None if seed > 100 else make_image(90, 70, seed)
    check(full_pattern, random_recipe(seed, blank=image is None), (97, 75), image)


@pytest.mark.parametrize("seed", [2, 9, 104])
def test_adaptive_stays_within_tolerance_of_full_pattern_on_noise(full_pattern, seed):
    """Noise is the hardest input for adaptive sampling: any position error shows."""
    renderer = fresh_renderer(adaptive=True)  # fresh: no busy frame seen before
    rng = np.random.default_rng(seed)
    noise = rng.integers(0, 256, (80, 100, 4), dtype=np.uint8)
    recipe = parse_recipe(random_recipe(seed) | {"antialias": "grid4"}, "noise.json")
    spec = recipe.at(recipe.end_time())
    geom = geometry(recipe.canvas, (120, 90), (100, 80))
    adaptive = renderer.render(spec, geom, noise)
    assert renderer.last_full_pixels < 120 * 90  # some pixels took the one-sample path
    assert agreement(adaptive, full_pattern.render(spec, geom, noise)) >= KERNEL_SHARE


def test_adaptive_samples_fully_only_near_edges(renderer):
    recipe = parse_recipe(
        {
            "marblevideo": 1,
            "canvas": [200, 200],
            "ops": [{"type": "drop", "center": [100, 100], "radius": 50, "color": [200, 0, 0]}],
        },
        "one-drop.json",
    )
    out = renderer.render(recipe.at(0), geometry(recipe.canvas, (200, 200)))
    assert out[100, 100, 0] == 200 and out[5, 5, 0] == 255
    # a circle of radius 50 crosses about 2*pi*50 pixels; each listed with its neighbours
    assert 300 < renderer.last_full_pixels < 1500


def test_busy_designs_take_the_full_pattern_after_a_busy_frame(full_pattern):
    """Where most pixels sit by an ink edge anyway (the nonpareil at its end),
    adaptive sampling costs more than the full pattern: after such a frame the
    next frames of that size and program take the full pattern, every eighth is
    adaptive again, and a new job starts adaptive."""
    from pathlib import Path

    from marblevideo.opencl.walks import BUSY_SHARE, PROBE_EVERY
    from marblevideo.recipe import load_recipe

    recipe = load_recipe(Path(__file__).parent.parent / "samples" / "nonpareil.json")
    spec, geom = recipe.at(recipe.end_time()), geometry(recipe.canvas, (240, 160))
    full = full_pattern.render(spec, geom)
    renderer = fresh_renderer()  # fresh: the busy-frame counts start from a new job
    listed = []
    for _ in range(2 * PROBE_EVERY + 1):
        out = renderer.render(spec, geom)
        listed.append(renderer.last_full_pixels)
        if listed[-1] is None:
            assert np.array_equal(out, full)
        else:
            assert agreement(out, full) >= KERNEL_SHARE
    assert listed[0] > BUSY_SHARE * 240 * 160
    assert [n is not None for n in listed] == ([True] + [False] * (PROBE_EVERY - 1)) * 2 + [True]
    # a calm frame (another program) between: adaptive, and the busy one after
    # it too (only the last frame is remembered); forget_frames: a new job
    calm = parse_recipe(
        {"canvas": recipe.canvas, "ops": [{"type": "drop", "center": [60, 40], "radius": 20,
                                          "color": "red"}]}, "calm.json",
    )  # fmt: skip
    renderer.render(calm.at(0), geom)
    assert 0 < renderer.last_full_pixels < BUSY_SHARE * 240 * 160
    for adaptive in (True, False):
        renderer.render(spec, geom)
        assert (renderer.last_full_pixels is not None) == adaptive
    renderer.forget_frames()
    renderer.render(spec, geom)
    assert renderer.last_full_pixels is not None


def test_vortex_centre_sample_is_not_nan(renderer):
    """A subsample exactly at a vortex centre (R = 0) has theta = 0, not NaN."""
    recipe = parse_recipe(
        {
            "marblevideo": 1,
            "canvas": [4, 4],
            "antialias": "none",
            "ops": [{"type": "vortex", "center": [2.5, 2.5], "alpha": 1e20, "lambda": 1}],
        },
        "centre.json",
    )
    image = make_image(4, 4, 2)
    spec = recipe.at(0)
    geom = geometry(recipe.canvas, (4, 4), (4, 4))
    ours = renderer.render(spec, geom, image)
    assert np.array_equal(ours[2, 2], reference_render(spec, geom, image)[2, 2])


CONCENTRIC = {
    "marblevideo": 1,
    "canvas": [120, 90],
    "antialias": "rgss",
    "ops": [
        {"type": "drop", "center": [60, 45], "radius": 20, "color": "#1d3557"},
        {"type": "drop", "center": [60, 45], "radius": 14, "color": "#e9c46a"},
        {"type": "drop", "center": [60, 45], "radius": 9, "color": "#b23a48"},
        {"type": "drop", "center": [64, 40], "radius": 6, "color": "#2a9d8f"},
        {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 24, "alpha": 10, "lambda": 6},
        {"type": "drop", "center": [30, 30], "radius": 8, "color": "#e76f51"},
        {
            "type": "drop",
            "center": [30, 30],
            "radius": {"keys": [{"t": 0, "v": 2}, {"t": 1, "v": 11}]},
            "color": "#f4f1de",
        },
    ],
}


def test_concentric_drops_walk_as_one_run():
    """Adjacent drops with one centre share one square root: the packed run."""
    from marblevideo.opencl.program import pack_params
    from marblevideo.ops.ink import RUN_MOVES, RUN_OFFSET

    rows = pack_params(parse_recipe(CONCENTRIC, "c.json").at(1.0)).params.reshape(7, -1)
    drops = [0, 1, 2, 3, 5, 6]  # walked last first: 6, 5 (a run), 3 (alone), 2, 1, 0 (a run)
    assert rows[drops, RUN_OFFSET].tolist() == [14**2 + 9**2, 9**2, 0, 0, 11**2, 0]
    assert rows[drops, RUN_MOVES].tolist() == [1, 0, 0, 1, 1, 0]
    assert rows[4, RUN_OFFSET] == 60 and rows[4, RUN_MOVES] == 6  # the comb's own values


@pytest.mark.parametrize("t", [0.0, 0.5, 1.0])
def test_concentric_runs_match_the_reference(renderer, full_pattern, t):
    image = make_image(100, 80, 3)
    for r in (renderer, full_pattern):
        check(r, CONCENTRIC, (120, 90), image, t)
        check(r, CONCENTRIC, (120, 90), None, t)


def test_ops_not_started_are_skipped_as_if_absent(full_pattern):
    """Ops still at a frame (before their start) are skipped by the walk: the
    frame equals, pixel for pixel, the render of the recipe without them, in the
    unrolled and the loop walk, a still drop at the head of a concentric run
    included (the run is linked over the drops walked)."""

    later = {"start": 5.0, "end": 6.0}
    drops = [
        {"type": "drop", "center": [60, 45], "radius": 20, "color": "#1d3557"},
        {"type": "drop", "center": [60, 45], "radius": 14, "color": "#e9c46a"},
    ]
    comb = {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 24, "alpha": 10, "lambda": 6}
    wave = {"type": "wave", "amplitude": 6, "wavelength": 40, "phase": 0, "angle": 30}
    with_still = {
        "canvas": [120, 90],
        "ops": [
            {"type": "drop", "center": [60, 45], "radius": 25, "color": "#b23a48", **later},
            *drops,
            {**comb, **later},
            wave,
            {"type": "rake", "point": [60, 45], "angle": 0, "alpha": 9, "falloff": 4,
             "spacing": 10, "count": 5, **later},
        ],
    }  # fmt: skip
    without = {"canvas": [120, 90], "ops": [*drops, wave]}
    geom = geometry((120, 90), (120, 90))
    image = make_image(100, 80, 5)
    for renderer in (full_pattern, fresh_renderer(adaptive=False, loop_walk=True)):
        for source in (None, image):
            a = renderer.render(parse_recipe(with_still, "s.json").at(1.0), geom, source)
            b = renderer.render(parse_recipe(without, "w.json").at(1.0), geom, source)
            assert np.array_equal(a, b)
    check(full_pattern, with_still, (120, 90), image, 1.0)
