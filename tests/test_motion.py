"""Format 1, revision 4: ``motion``, what moves in front of the camera stirs the ink.

The recipe's ``motion`` object is validated like every field (one line, its JSON
path, exit 2); the analysis holds the contract's cases exactly as written on clips
made in NumPy (tests/support/motion_clips.py, 640x360 at 30 fps, where a pixel is
a canvas unit): no stroke from sensor noise or a shaken camera, one stroke per
textured disc (D 40..160 px, 100..600 px/s, along a line or an arc) that follows
it, two for two discs apart; the same frames give the same strokes bit for bit;
healed strokes leave what is rendered; a StirredRecipe renders on the device as
the reference renders its take."""

from __future__ import annotations

import json
import math

import cv2
import numpy as np
import pytest
from helpers import assert_refused
from motion_clips import Disc, arc, disc_clip, line, noise_clip, shake_clip
from tolerances import KERNEL_SHARE

from marblevideo.errors import RecipeError
from marblevideo.motion import MotionSpec, MotionTracker, StirredRecipe, luma
from marblevideo.opencl.selfcheck import agreement
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.recipe.schema import schema
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

SIZE = (640, 360)
IDENTITY = (1.0, 1.0, 0.0, 0.0)


def motion_doc(motion: object) -> dict:
    return {"canvas": [64, 36], "ops": [], "motion": motion}


def track(clip, spec: MotionSpec | None = None, to_canvas=IDENTITY) -> MotionTracker:
    tracker = MotionTracker(spec or MotionSpec(), to_canvas)
    for frame, t in clip:
        tracker.see(frame, t)
    return tracker


# ---------------------------------------------------------------------------- the recipe


def test_motion_fields_take_the_contracts_defaults():
    assert parse_recipe(motion_doc({})).motion == MotionSpec()
    assert parse_recipe({"canvas": [4, 4], "ops": []}).motion is None
    given = {"gain": 2.5, "width": [10, 10], "threshold": 0, "max_strokes": 32, "memory": 0.5}
    spec = parse_recipe(motion_doc({**given, "heal": 0})).motion
    assert spec == MotionSpec(2.5, (10.0, 10.0), 0.0, 32, 0.5, 0.0)
    assert parse_recipe(motion_doc({})).is_animated
    published = schema()["properties"]["motion"]["properties"]
    assert {k: v["default"] for k, v in published.items()} == MotionSpec().to_json()


@pytest.mark.parametrize(
    ("motion", "path", "expected"),
    [
        ({"gain": 4.5}, "motion.gain", "<= 4"),
        ({"gain": -1}, "motion.gain", ">= 0"),
        ({"width": [50, 20]}, "motion.width", "min <= max"),
        ({"width": [0, 20]}, "motion.width[0]", "> 0"),
        ({"width": [20]}, "motion.width", "[min, max], got a list of 1"),
        ({"threshold": -1}, "motion.threshold", ">= 0"),
        ({"max_strokes": 0}, "motion.max_strokes", ">= 1"),
        ({"max_strokes": 33}, "motion.max_strokes", "<= 32"),
        ({"max_strokes": 2.5}, "motion.max_strokes", "integer"),
        ({"memory": 0.25}, "motion.memory", ">= 0.5"),
        ({"heal": -0.5}, "motion.heal", ">= 0"),
        ({"speed": 1}, "motion", "speed"),
        (3, "motion", "object"),
    ],
)
def test_a_bad_motion_is_refused_with_its_path(motion, path, expected):
    with pytest.raises(RecipeError) as caught:
        parse_recipe(motion_doc(motion), "r.json")
    assert str(caught.value).startswith(f"r.json: {path}: "), str(caught.value)
    assert expected in str(caught.value), str(caught.value)


@pytest.mark.parametrize(
    ("motion", "path", "expected"),
    [
        ({"gain": 5}, "motion.gain", "<= 4"),
        ({"width": [50, 20]}, "motion.width", "min <= max"),
        ({"follow": True}, "motion", "follow"),
    ],
)
def test_the_cli_refuses_a_bad_motion_in_one_line(cli, tmp_path, motion, path, expected):
    assert_refused(cli, tmp_path, json.dumps(motion_doc(motion)), path, expected)


# ---------------------------------------------------------------------------- the analysis


def test_luma_is_one_definition_for_rgb_rgba_and_luma_frames():
    rgb = np.random.default_rng(0).integers(0, 256, (9, 7, 3), dtype=np.uint8)
    rgba = np.concatenate([rgb, np.full((9, 7, 1), 17, np.uint8)], axis=2)
    gray = luma(rgb)
    assert gray.shape == (9, 7) and gray.dtype == np.uint8
    assert np.array_equal(luma(rgba), gray) and np.array_equal(luma(gray), gray)
    weighted = rgb.astype(np.float64) @ [0.299, 0.587, 0.114]
    assert np.abs(gray - weighted).max() <= 0.5 + 1e-6


@pytest.mark.parametrize("size", [(1, 1), (7, 5), (3000, 10), (15, 400)])
def test_a_frame_too_small_to_analyse_shows_no_motion(size):
    tracker = MotionTracker(MotionSpec(), IDENTITY)
    rng = np.random.default_rng(0)
    for n in range(4):
        tracker.see(rng.integers(0, 256, (size[1], size[0], 3), dtype=np.uint8), n / 30)
    assert tracker.take() == [] and tracker.regions() == [] and tracker.level() == 0


@pytest.mark.slow
@pytest.mark.parametrize("make", [noise_clip, shake_clip], ids=["sensor-noise", "shaken-camera"])
def test_noise_and_a_shaken_camera_make_no_stroke(make):
    """Sensor noise of 4 levels' standard deviation; a camera shaken by up to 4 px a frame."""
    tracker = track(make(4.0, SIZE))
    assert tracker.take() == []


def follows(stroke: dict, disc: Disc) -> None:
    """The contract's case: the stroke follows ``disc`` while it moves."""
    d = disc.diameter
    for point, t in zip(stroke["points"], stroke["times"], strict=True):
        assert math.dist(point, disc.center(t)) <= max(8.0, d / 4), (t, point, disc.center(t))
    assert abs(stroke["times"][0] - disc.t0) <= 0.2, stroke["times"][0]
    assert abs(stroke["times"][-1] - disc.t1) <= 0.2, stroke["times"][-1]
    low, high = MotionSpec().width
    assert d / 2 <= stroke["width"] <= 1.5 * d and low <= stroke["width"] <= high


def moving_disc(d: float, speed: float, path: str, size=SIZE) -> Disc:
    w, h = size
    if path == "line":
        seconds = min(1.0, (w - d - 60) / speed)
        return Disc(d, (30 + d / 2, h / 2), line(speed), 0.3, 0.3 + seconds)
    radius = h / 2 - d / 2 - 10
    seconds = min(1.0, math.pi * radius / speed)
    return Disc(d, (w / 2, d / 2 + 10), arc(speed, radius), 0.3, 0.3 + seconds)


@pytest.mark.slow
@pytest.mark.parametrize("size", [(320, 180), (640, 360)], ids=["unreduced", "reduced"])
def test_a_luma_plane_with_padded_rows_makes_the_take_of_its_copy(size):
    """A decoder's Y plane (rows padded past the width) is analysed where it lies,
    reduced or not: the same take, bit for bit, as its contiguous copy."""
    disc = moving_disc(60, 300, "line", size)
    clip = disc_clip([disc], size, seconds=disc.t1 + 0.3)
    planes = [luma(frame) for frame in clip.frames]
    padded = [np.pad(plane, ((0, 0), (0, 64)))[:, : size[0]] for plane in planes]
    assert not padded[0].flags.c_contiguous
    take = track(zip(planes, clip.times, strict=True)).take()
    assert len(take) == 1
    assert track(zip(padded, clip.times, strict=True)).take() == take


@pytest.mark.slow
@pytest.mark.parametrize("path", ["line", "arc"])
@pytest.mark.parametrize("speed", [100, 300, 600])
@pytest.mark.parametrize("d", [40, 100, 160])
def test_a_moving_disc_makes_one_stroke_that_follows_it(d, speed, path):
    disc = moving_disc(d, speed, path)
    tracker = track(disc_clip([disc], SIZE, seconds=disc.t1 + 0.5))
    take = tracker.take()
    assert len(take) == 1, [(s["times"][0], s["times"][-1]) for s in take]
    follows(take[0], disc)
    assert take[0]["drag"] == 1.0 and take[0]["heal"] == [
        take[0]["times"][-1] + 6.0,
        take[0]["times"][-1] + 6.0 + 2.0,
    ]


@pytest.mark.slow
@pytest.mark.parametrize(("speed", "path"), [(100, "line"), (600, "arc")])
def test_at_720p_a_disc_of_100_px_makes_one_stroke_that_follows_it(speed, path):
    """At 1280x720 the luma is reduced by 4 (docs/recipe-format.md: a 40 px disc is
    not followed surely there; 100 px is)."""
    disc = moving_disc(100, speed, path, (1280, 720))
    take = track(disc_clip([disc], (1280, 720), seconds=disc.t1 + 0.4)).take()
    assert len(take) == 1
    follows(take[0], disc)


@pytest.mark.slow
def test_two_discs_apart_make_two_strokes_each_following_its_own():
    w, h = SIZE
    discs = [
        Disc(60, (60, 80), line(300), 0.3, 1.3),
        Disc(90, (w - 70, h - 80), line(250, 180), 0.4, 1.4, seed=9),
    ]
    clip = disc_clip(discs, SIZE, seconds=1.8)
    take = track(clip).take()
    assert len(take) == 2
    owners = [
        min(range(2), key=lambda n: math.dist(s["points"][0], discs[n].center(s["times"][0])))
        for s in take
    ]
    assert sorted(owners) == [0, 1]
    for stroke, owner in zip(take, owners, strict=True):
        follows(stroke, discs[owner])


@pytest.mark.slow
def test_max_strokes_follows_the_largest_area_times_speed_first():
    w, h = SIZE
    small = Disc(50, (60, 80), line(300), 0.3, 1.1)
    large = Disc(110, (w - 80, h - 90), line(300, 180), 0.3, 1.1, seed=9)
    take = track(disc_clip([small, large], SIZE, seconds=1.5), MotionSpec(max_strokes=1)).take()
    assert len(take) == 1
    follows(take[0], large)


def paused(speed: float, moving: float, pause: float):
    """Along +x at ``speed``, still for ``pause`` s after ``moving`` s, then on."""
    return lambda s: (speed * (s if s < moving else max(moving, s - pause)), 0.0)


@pytest.mark.slow
@pytest.mark.parametrize(("pause", "strokes"), [(0.1, 1), (0.6, 2)])
def test_a_pause_longer_than_a_quarter_second_ends_the_stroke(pause, strokes):
    disc = Disc(80, (70, 180), paused(300, 0.5, pause), 0.3, 0.8 + pause + 0.5)
    take = track(disc_clip([disc], SIZE, seconds=disc.t1 + 0.4)).take()
    assert len(take) == strokes, [(s["times"][0], s["times"][-1]) for s in take]
    for stroke in take:
        for point, t in zip(stroke["points"], stroke["times"], strict=True):
            assert math.dist(point, disc.center(t)) <= 20
    if strokes == 2:
        assert take[0]["times"][-1] <= 0.8 + 0.2 and take[1]["times"][0] >= 0.8 + pause


@pytest.mark.parametrize("fit", [None, "stretch", "crop", "pad"])
def test_frame_points_map_to_the_canvas_as_the_render_samples_them(fit):
    """frame_to_canvas inverts the render's canvas -> input map (Geometry.to_input)."""
    from marblevideo.motion.stirred import frame_to_canvas

    canvas, size, out = (400.0, 300.0), (640, 360), (800, 600)
    a, b, c, d = frame_to_canvas(canvas, size, fit, out)
    sx, sy, ox, oy = geometry(canvas, out, size, None, fit).to_input
    for cx, cy in [(0.0, 0.0), (123.5, 77.25), (400.0, 300.0)]:
        px, py = cx * sx + ox, cy * sy + oy
        assert (px * a + c, py * b + d) == pytest.approx((cx, cy), abs=1e-9)


SHORT = [Disc(60, (60, 180), line(300), 0.2, 0.9)]


@pytest.fixture(scope="module")
def short_clip():
    return disc_clip(SHORT, SIZE, seconds=1.3)


def test_the_same_frames_give_the_same_strokes_whatever_the_threads(short_clip):
    first = track(short_clip).take()
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    try:
        again = track(short_clip).take()
    finally:
        cv2.setNumThreads(threads)
    assert first and json.dumps(first) == json.dumps(again)


def test_strokes_heal_and_leave_what_is_rendered(short_clip):
    spec = MotionSpec(memory=0.5, heal=0.2)
    tracker = MotionTracker(spec, IDENTITY)
    still = [(short_clip.frames[-1], n / 30) for n in range(len(short_clip.times), 60)]
    seen = []
    for frame, t in [*short_clip, *still]:
        tracker.see(frame, t)
        seen.append((t, tracker.strokes(), tracker.level(), tracker.regions()))
    (stroke,) = tracker.take()
    t0, t1 = stroke["heal"]
    assert t1 - t0 == pytest.approx(0.2) and t0 == pytest.approx(stroke["times"][-1] + 0.5)
    assert t1 < 59 / 30
    for t, strokes, level, regions in seen:
        alive = stroke["times"][1] <= t < t1  # made at its 2nd point (the identity at its 1st)
        assert len(strokes) == int(alive), t
        if alive and t >= stroke["times"][-1]:
            assert strokes == [stroke]
        if SHORT[0].t0 + 0.1 < t < SHORT[0].t1:
            assert 0 < level <= 1 and [r["stroke"] for r in regions] == [0]
            assert math.dist(regions[0]["center"], SHORT[0].center(t)) <= 15
        if t > SHORT[0].t1 + 0.1:
            assert level == 0 and regions == []


def test_a_stroke_past_the_step_limit_goes_on_as_a_new_one(short_clip):
    """A thin stroke (width 0.01: 200 000 steps are 500 canvas units) is split where
    it would pass the stroke op's step limit, each part a valid stroke."""
    spec = MotionSpec(width=(0.01, 0.01))
    take = track(short_clip, spec, (4.0, 4.0, 0.0, 0.0)).take()  # the disc moves 840 units
    assert len(take) >= 2
    assert take[1]["points"][0] == take[0]["points"][-1]
    parse_recipe({"canvas": [2560, 1440], "ops": take})


# ---------------------------------------------------------------------------- stirred recipes


def rgba(frame: np.ndarray) -> np.ndarray:
    return np.dstack([frame, np.full(frame.shape[:2], 255, np.uint8)])


def test_a_stirred_recipe_renders_as_the_reference_renders_its_take(renderer, short_clip):
    """Over a 640x360 input with a 320x180 canvas (canvas = frame / 2): what see()
    returns renders on the device as the reference renders the take document at
    that time, and the reference renders both alike exactly."""
    document = {
        "canvas": [320, 180],
        "ops": [{"type": "drop", "center": [160, 90], "radius": 30, "color": "#1d3557"}],
        "motion": {"gain": 1.5, "memory": 0.5, "heal": 0.5},
    }
    stirred = StirredRecipe(parse_recipe(document), SIZE)
    checked = 0
    for frame, t in short_clip:
        recipe = stirred.see(frame, t)
        assert recipe.motion is None and recipe.ops[0].type == "drop"
        plain = {"canvas": [320, 180], "ops": [*document["ops"], *stirred.tracker.strokes()]}
        assert recipe.ops == parse_recipe(plain).ops  # as if the file held the strokes
        if round(t * 30) not in (15, 27, 36):
            continue
        strokes = recipe.ops[1:]
        assert len(strokes) == 1 and all(op.type == "stroke" for op in strokes)
        point = strokes[0].params["points"].at(t)[-2:]
        assert math.dist(point, [c / 2 for c in SHORT[0].center(t)]) <= 8
        take = parse_recipe(stirred.take_document(document))
        geom = geometry((320.0, 180.0), (160, 90), SIZE)
        image = rgba(frame)
        spec, spec_take = recipe.at(t), take.at(t)
        expected = reference_render(spec_take, geom, image)
        assert np.array_equal(reference_render(spec, geom, image), expected)
        assert agreement(renderer.render(spec, geom, image), expected) >= KERNEL_SHARE
        checked += 1
    assert checked == 3
    late = stirred.see(short_clip.frames[-1], 2.5)  # healed at 0.9 + 0.5 + 0.5
    assert len(late.ops) == 1 and "motion" not in stirred.take_document(document)


def test_a_stirred_recipe_is_the_same_object_while_nothing_changes(short_clip):
    stirred = StirredRecipe(parse_recipe({"ops": [], "motion": {}}), SIZE)
    first = stirred.see(short_clip.frames[0], 0.0)
    assert stirred.see(short_clip.frames[1], 1 / 30) is first and first.ops == ()
