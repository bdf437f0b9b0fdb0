"""The interpolated inverse map of animated frames (marblevideo.opencl.lattice).

Frames interpolated from the lattice are checked against the exact walk of the
same renderer (itself checked against the NumPy reference elsewhere), on scenes
where interpolation cannot be trusted: a drop edge, a thin filament, a sharp
vortex core, a drop smaller than the lattice. Each scene is also rendered with
the rule that should catch it switched off, to show that the scene fails then:
the tests fail when a refinement rule is broken.
"""

from __future__ import annotations

import numpy as np
import pytest
from clips import probe
from helpers import fresh_renderer
from recipes import random_registry_op

from marblevideo.errors import RecipeError
from marblevideo.marbler import Marbler
from marblevideo.media.yuv import YuvMatrix
from marblevideo.opencl.lattice import RULE_CENTRE, RULE_INK, RULES, LatticeWalk
from marblevideo.opencl.renderer import Renderer
from marblevideo.ops import REGISTRY
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference.yuv import rgba_to_i420

pytestmark = pytest.mark.tier("fast")

W, H = 192, 128
#: With every rule: the share of pixels within 2 levels of the exact walk, and the
#: largest difference (a position off by up to TOLERANCE input pixels on a hard
#: edge of the input, the checker's, moves its colour by up to 255 / 16 levels;
#: these small frames are mostly such edges and ink edges).
WITHIN2, LARGEST = 0.98, 24
#: With the scene's rule switched off, some pixel is at least this far off.
BROKEN = 128

SCENES = {
    "drop edge": (
        [{"type": "drop", "center": [90, 60], "radius": 30, "color": "#203050"}],
        RULE_INK,
    ),
    "thin filament": (
        [
            {"type": "drop", "center": [96, 64], "radius": 24, "color": "#203050"},
            {"type": "tine", "point": [0, 64], "angle": 0, "alpha": 140, "lambda": 3},
        ],
        RULE_INK | RULE_CENTRE,
    ),
    "sharp vortex core": (
        [{"type": "vortex", "center": [96, 64], "alpha": 600, "lambda": 3}],
        RULE_CENTRE,
    ),
    "drop between lattice points": (
        [{"type": "drop", "center": [98, 66], "radius": 1.5, "color": "#203050"}],
        RULE_CENTRE,
    ),
}


def clip_picture(w: int = W, h: int = H) -> np.ndarray:
    """The benchmark clip's kind of picture (RGBA): two ramps and a 40-pixel checker."""
    yy, xx = np.mgrid[0:h, 0:w]
    planes = [(xx + 200) % 256, (yy * 2 + 50) % 256, (xx // 40 + yy // 40) % 2 * 255]
    return np.stack([*planes, np.full_like(xx, 255)], axis=2).astype(np.uint8)


def recipe_of(ops: list, **extra) -> dict:
    return {"marblevideo": 1, "canvas": [W, H], "antialias": "rgss", "ops": ops, **extra}


def diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = np.abs(a.astype(np.int16) - b.astype(np.int16))
    return d.max(axis=2) if d.ndim == 3 else d


def lattice_renderer(**options) -> Renderer:
    """A renderer whose lattice takes frames of any number of ops (the scenes
    have one or two; by default such frames are walked: MIN_WALKED_OPS)."""
    renderer = fresh_renderer(**options)
    renderer.lattice_walk.min_ops = 1
    return renderer


@pytest.fixture(scope="module")
def walker():
    return lattice_renderer(reuse_maps=False)


def frames(renderer: Renderer, ops: list, rules: int = RULES, image=None):
    """(exact, from the lattice) RGBA frames of ``ops`` over ``image``."""
    image = clip_picture() if image is None else image
    h, w = image.shape[:2]
    recipe = parse_recipe(recipe_of(ops), "scene.json")
    spec, geom = recipe.at(0.0), geometry(recipe.canvas, (w, h), (w, h))
    exact = renderer.render(spec, geom, image)
    renderer.lattice_walk.rules = rules
    try:
        return exact, renderer.render(spec, geom, image, lattice=True)
    finally:
        renderer.lattice_walk.rules = RULES


@pytest.mark.parametrize("name", list(SCENES))
def test_cells_the_lattice_cannot_follow_are_walked(walker, name):
    ops, _ = SCENES[name]
    exact, lattice = frames(walker, ops)
    d = diff(exact, lattice)
    assert (d <= 2).mean() >= WITHIN2 and d.max() <= LARGEST
    assert 0.0 < walker.lattice_walk.refined_share() < 1.0


@pytest.mark.parametrize("name", list(SCENES))
def test_each_scene_fails_without_its_rule(walker, name):
    ops, rule = SCENES[name]
    exact, lattice = frames(walker, ops, RULES & ~rule)
    assert diff(exact, lattice).max() >= BROKEN


def test_a_smooth_map_is_interpolated_everywhere(walker):
    ops = [
        {"type": "wave", "amplitude": 3, "wavelength": 200, "phase": 0, "angle": 90},
        {"type": "turn", "center": [96, 64], "angle": 5},
    ]
    exact, lattice = frames(walker, ops)
    assert walker.lattice_walk.refined_share() == 0.0
    d = diff(exact, lattice)
    assert (d <= 2).mean() >= WITHIN2 and d.max() <= LARGEST


def test_a_linear_map_is_interpolated_within_a_level(walker):
    exact, lattice = frames(walker, [{"type": "turn", "center": [96, 64], "angle": 20}])
    assert walker.lattice_walk.refined_share() == 0.0
    assert diff(exact, lattice).max() <= 1


@pytest.mark.parametrize("lanes", [1, 8])
def test_every_lane_width_interpolates_alike(lanes):
    renderer = lattice_renderer(lanes=lanes, chains=1 if lanes == 1 else 2, reuse_maps=False)
    exact, lattice = frames(renderer, SCENES["thin filament"][0])
    d = diff(exact, lattice)
    assert (d <= 2).mean() >= WITHIN2 and d.max() <= LARGEST


def test_planes_interpolate_from_one_lattice(walker):
    matrix = YuvMatrix.of(1, 1)
    recipe = parse_recipe(recipe_of(SCENES["thin filament"][0]), "scene.json")
    spec, geom = recipe.at(0.0), geometry(recipe.canvas, (W, H), (W, H))
    planes = rgba_to_i420(clip_picture(), matrix)
    exact = walker.render_i420(spec, geom, planes, matrix, matrix)
    lattice = walker.render_i420(spec, geom, planes, matrix, matrix, lattice=True)
    d = diff(exact, lattice)
    assert (d <= 2).mean() >= WITHIN2 and d.max() <= LARGEST
    assert 0.0 < walker.lattice_walk.refined_share() < 1.0


def test_frames_of_few_ops_are_walked_exactly():
    renderer = fresh_renderer(reuse_maps=False)  # fresh: counts its lattice frames
    frames(renderer, SCENES["thin filament"][0])  # two ops
    assert renderer.lattice_walk.frames == 0
    frames(renderer, [*SCENES["thin filament"][0], SCENES["sharp vortex core"][0][0]])
    assert renderer.lattice_walk.frames == 1


def test_a_gpu_walks_every_frame_exactly():
    """A GPU walks faster than it interpolates (BENCHMARKS.md, session 14): its
    lattice takes no frame by default, whatever the number of ops."""
    renderer = fresh_renderer(reuse_maps=False)  # fresh: its lattice is replaced
    renderer.lattice_walk = LatticeWalk(renderer.device_queue, renderer.lanes, gpu=True)
    frames(renderer, [*SCENES["thin filament"][0], SCENES["sharp vortex core"][0][0]])
    assert renderer.lattice_walk.frames == 0


def test_repeated_values_keep_their_stored_maps():
    renderer = lattice_renderer()
    recipe = parse_recipe(recipe_of(SCENES["drop edge"][0]), "scene.json")
    spec, geom = recipe.at(0.0), geometry(recipe.canvas, (W, H), (W, H))
    renderer.render(spec, geom, clip_picture(), lattice=True)
    assert not renderer.last_reused
    renderer.render(spec, geom, clip_picture(), lattice=True)
    assert renderer.last_reused


def animated(**extra) -> dict:
    ops = [
        {
            "type": "vortex",
            "center": [96, 64],
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 2, "v": 90}]},
            "lambda": 30,
        }
    ]
    return recipe_of(ops, **extra)


def test_video_frames_use_the_lattice_unless_turned_off(walker):
    assert Marbler(animated(), walker).transform().route.lattice
    assert not Marbler(animated(), walker, lattice=False).transform().route.lattice
    assert not Marbler(animated(lattice=False), walker).transform().route.lattice
    assert (
        not Marbler(recipe_of(SCENES["drop edge"][0]), walker).transform().route.lattice
    )  # static


def test_stills_walk_every_subsample():
    renderer = lattice_renderer(reuse_maps=False)
    marbler = Marbler(animated(), renderer)
    marbler.render(clip_picture(), 1.0)
    assert renderer.lattice_walk.refined_share() is None
    marbler.render(clip_picture(), 1.0, animated=True)
    assert renderer.lattice_walk.refined_share() is not None


def test_the_recipe_field_must_be_a_boolean(cli, tmp_path):
    import json

    from helpers import one_line

    recipe = tmp_path / "r.json"
    recipe.write_text(json.dumps(animated(lattice="no")))
    proc = cli("--ops", str(recipe), "-o", str(tmp_path / "o.png"))
    assert proc.returncode == 2
    assert "lattice" in one_line(proc) and "r.json" in one_line(proc)


def test_exact_walk_applies_to_video_outputs(cli, tmp_path):
    import json

    from helpers import one_line

    recipe = tmp_path / "r.json"
    recipe.write_text(json.dumps(animated()))
    proc = cli("--ops", str(recipe), "-o", str(tmp_path / "o.png"), "--exact-walk")
    assert proc.returncode == 2
    assert "--exact-walk" in one_line(proc)


@pytest.mark.parametrize("exact_walk", [False, True])
def test_a_video_job_takes_the_lattice_unless_exact_walk(tmp_path, exact_walk):
    from clips import write_clip

    from marblevideo.api import render_video

    clip = write_clip(tmp_path / "in.mp4", size=(W, H), frames=6, audio=False)
    renderer = lattice_renderer()
    out = tmp_path / "out.mp4"
    render_video(clip, animated(), out, renderer=renderer, exact_walk=exact_walk, quiet=True)
    assert out.stat().st_size > 0
    walked = renderer.lattice_walk.refined_share()
    assert (walked is None) == exact_walk


@pytest.mark.parametrize("definition", list(REGISTRY.values()), ids=list(REGISTRY))
def test_every_op_type_goes_through_the_lattice(walker, definition):
    """Any op, walked generically: random instances over a drop agree with the
    exact walk (every pixel whose cell is interpolated or one ink included)."""
    rng = np.random.default_rng(definition.code)
    for _ in range(3):
        for _attempt in range(200):
            op = random_registry_op(rng, definition, W, H)
            try:
                parse_recipe(recipe_of([SCENES["drop edge"][0][0], op]), "r.json")
            except RecipeError:
                continue
            break
        exact, lattice = frames(walker, [SCENES["drop edge"][0][0], op])
        d = diff(exact, lattice)
        assert (d <= 2).mean() >= WITHIN2, op


def test_segments_keep_exact_walk(tmp_path):
    """--cluster: every segment walks as the job asks (at crf 0 a lattice frame
    would differ from the single exact render in some pixels)."""
    from clips import write_clip

    from marblevideo.api import render_video
    from marblevideo.scale.segmented import render_split

    clip = write_clip(tmp_path / "in.mp4", size=(W, H), frames=12, audio=False)
    ops = [*SCENES["thin filament"][0], *animated()["ops"]]
    recipe = recipe_of(ops)
    single = tmp_path / "single.mp4"
    render_video(clip, recipe, single, crf=0, exact_walk=True, quiet=True)
    split = tmp_path / "split.mp4"
    render_split(clip, recipe, split, cluster="serial", segments=2, crf=0, exact_walk=True,
                 quiet=True)  # fmt: skip
    lattice = tmp_path / "lattice.mp4"
    render_video(clip, recipe, lattice, crf=0, quiet=True)
    a, b, c = (probe(p).frames for p in (single, split, lattice))
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
    assert not all(np.array_equal(x, y) for x, y in zip(a, c, strict=True))
