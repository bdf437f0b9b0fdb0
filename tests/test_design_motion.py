"""The recipe's ``motion`` in the designer over a live source or a video
(:mod:`marblevideo.design.motion`): the backdrop's frames feed one tracker, the
renders carry its strokes, ``/api/motion`` reports them as in ``marblevideo
live``, and a recipe without ``motion`` runs no tracker.

The source is a file played live (the clip of ``motion_clips``: a textured disc
crossing a still textured background, encoded with PyAV), behind the real
designer session and its HTTP server; ``marblevideo design test`` (its page in
a real headless Chromium: the meter and the overlay of the motion); and
``marblevideo design`` over the clip as a video, against the file render's take.
"""

from __future__ import annotations

import contextlib
import json
import math
import time
import urllib.request

import numpy as np
import pytest
from helpers import fresh_renderer
from live_helpers import LiveProcess, designer_page, wait_for
from motion_clips import Disc, disc_clip, line
from motion_video import encode_clip

from marblevideo.design.backdrop import LiveFeed
from marblevideo.design.layers import HEADER
from marblevideo.design.session import DesignSession
from marblevideo.live.sources import MediaSource
from marblevideo.serve.recipefile import RecipeFile
from marblevideo.serve.server import Server

pytestmark = pytest.mark.tier("integration")

D = 80  # the disc's diameter, px
DISC = Disc(D, (100, 180), line(300), 0.3, 1.3)  # crosses 300 px from 0.3 s to 1.3 s
RECIPE = {"marblevideo": 1, "antialias": "none", "motion": {}, "ops": []}
PLAIN = {k: v for k, v in RECIPE.items() if k != "motion"}
WAVE = {"type": "wave", "amplitude": 4, "wavelength": 120, "phase": 0, "angle": 90}


@pytest.fixture(scope="module")
def loop_renderer():
    return fresh_renderer(loop_walk=True)  # the designer's: one program for any ops


@contextlib.contextmanager
def designer(tmp_path, recipe: dict, renderer, loop: bool = False):
    """The designer over the disc clip (480x360, 3 s) played as a live source
    (``loop``: again and again), serving ``recipe``: (its URL, its backdrop)."""
    clip = disc_clip([DISC], size=(480, 360), seconds=3.0, fps=30)
    path = encode_clip(clip, tmp_path / "disc.mp4")
    (tmp_path / "r.json").write_text(json.dumps(recipe))
    backdrop = LiveFeed("disc", source=MediaSource(str(path), loop=loop))
    session = DesignSession(RecipeFile(tmp_path / "r.json"), backdrop, renderer=renderer)
    server = Server(session, 0)
    try:
        session.start()
        server.start()
        yield server.url.rstrip("/"), backdrop
    finally:
        server.stop()
        session.close()
        backdrop.close()


def get(url: str):
    with urllib.request.urlopen(url, timeout=30) as r:
        body = r.read()
        return json.loads(body) if r.headers.get_content_type() == "application/json" else body


def send(url: str, obj, method: str = "POST") -> bytes:
    data = json.dumps(obj).encode()
    req = urllib.request.Request(url, data, {"Content-Type": "application/json"}, method=method)
    with urllib.request.urlopen(req, timeout=30) as r:
        return r.read()


def pixels(raw: bytes) -> np.ndarray:
    w, h = np.frombuffer(raw[:8], "<u4")
    return np.frombuffer(raw[8:], np.uint8).reshape(h, w, 4)


def until(pred, what: str, timeout: float = 30.0):
    end = time.monotonic() + timeout
    while not (value := pred()):
        assert time.monotonic() < end, what
        time.sleep(0.1)
    return value


def test_the_designer_over_a_live_source_stirs_with_its_motion(tmp_path, loop_renderer):
    with designer(tmp_path, RECIPE, loop_renderer) as (url, backdrop):
        until(lambda: backdrop.source.ended, "the clip played to its end", 60)
        time.sleep(0.3)  # its last frame taken
        state = get(url + "/api/motion")
        assert state["t"] == get(url + "/api/motion")["t"]  # no frame since
        meter = get(url + "/api/motion?shapes=0")
        assert get(url + "/api/info")["input"]["kind"] == "live"
        # the saved recipe keeps its motion: nothing is written into the file
        assert json.loads((tmp_path / "r.json").read_text()) == RECIPE
        at = f"/api/frame.rgba?t={state['t']!r}"  # the strokes as the last frame left them
        with_motion = pixels(get(url + at))
        without = pixels(send(url + at, PLAIN))
        take = pixels(send(url + at, {**PLAIN, "ops": state["strokes"]}))
        # a gesture on the last op: the strokes lie above it, in the map of the ops above
        layers = f"/api/layers?k=0&t={state['t']!r}&w=240"
        above = [
            HEADER.unpack_from(send(url + layers, {**r, "ops": [WAVE]}))[3] for r in (RECIPE, PLAIN)
        ]
    assert state["active"] and state["frames"] > 30 and 2.5 <= state["t"] <= 3.0
    assert {f["name"] for f in state["fields"]} >= {"gain", "width", "heal"}
    assert meter["regions"] == meter["strokes"] == [] and meter["frames"] >= state["frames"]
    # the strokes follow the disc (a loaded machine drops frames: within D/2)
    dropped = backdrop.source.frames.dropped
    strokes = state["strokes"]
    assert strokes and all(op["type"] == "stroke" for op in strokes)
    for op in strokes:
        for point, t in zip(op["points"], op["times"], strict=True):
            within = max(8, D / 4) if dropped == 0 else D / 2
            assert math.dist(point, DISC.center(t)) <= within, (point, t, DISC.center(t))
    # over the same (last) frame: the render is of the recipe and the strokes
    # reported, which move the pixels along the disc's path most
    assert np.array_equal(with_motion, take)
    assert above == [1, 0]
    moved = np.abs(with_motion[..., :3].astype(int) - without[..., :3]).max(axis=-1) > 24
    assert moved[140:220, 100:400].mean() > 0.5
    assert moved[:40].mean() < 0.02 and moved[320:].mean() < 0.02


def test_a_recipe_without_motion_runs_no_tracker_until_motion_is_saved(tmp_path, loop_renderer):
    plain = {**PLAIN, "ops": [WAVE]}
    with designer(tmp_path, plain, loop_renderer, loop=True) as (url, backdrop):
        time.sleep(1.5)
        idle = get(url + "/api/motion")
        assert "frames" not in idle and not idle["active"] and idle["strokes"] == []
        assert get(url + "/api/frame.rgba?t=0")  # renders, without a tracker
        # motion saved as the page saves it: the next frames are tracked
        send(url + "/api/recipe", {**plain, "motion": {"gain": 2}}, "PUT")
        state = until(
            lambda: (m := get(url + "/api/motion"))["active"] and m["frames"] > 5 and m,
            "the tracker sees the frames once motion is saved",
        )
        assert state["t"] > 0


def test_marblevideo_design_test_tracks_the_test_pattern(tmp_path):
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    app = LiveProcess(
        "test", "--ops", "r.json", "--size", "320x180", "--no-browser", "--port", "0",
        "--duration", "60", "-q", cwd=tmp_path, command="design",
    )  # fmt: skip
    try:
        state = until(
            lambda: (m := app.get("/api/motion"))["active"] and m["frames"] > 10 and m,
            "the test pattern's frames are tracked",
        )
        assert 0 <= state["level"] <= 1
        assert len(app.get("/api/frame.rgba?t=0&w=160")) == 8 + 160 * 90 * 4
    finally:
        assert app.stop() == 0, app.stderr()


def test_the_page_over_a_live_source_meters_shows_and_edits_the_motion(browser, tmp_path):
    recipe = tmp_path / "r.json"
    recipe.write_text(json.dumps(RECIPE))
    args = ("test", "--ops", recipe, "--size", "320x180")
    with designer_page(browser, tmp_path, *args, duration=120) as (page, errors):
        assert page.is_visible("#motion-level") and page.is_visible("#motion-show")
        level = lambda: float(page.get_attribute("#motion-level", "data-level"))  # noqa: E731
        wait_for(lambda: level() > 0, "the meter never showed the pattern's moving disc")
        page.check("#motion-show")
        circles = "JSON.parse(document.getElementById('overlay').dataset.circles || '[]')"
        wait_for(lambda: page.evaluate(circles), "no region drawn over the sheet")
        page.fill("#motion-gain", "2")
        page.press("#motion-gain", "Enter")
        wait_for(lambda: json.loads(recipe.read_text()).get("motion") == {"gain": 2}, "not saved")
        assert errors == []


def test_the_designer_over_a_video_shows_the_strokes_a_file_render_makes(cli, tmp_path):
    """A video backdrop is sought by time; its motion is read from the file in
    order up to the time shown: the strokes of the file render's take."""
    encode_clip(disc_clip([DISC], size=(480, 360), seconds=2.0, fps=30), tmp_path / "disc.mp4")
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    done = cli("disc.mp4", "--ops", "r.json", "-o", "out.mp4", "--automation", "take.json", "-q")
    assert done.returncode == 0, done.stderr
    take = json.loads((tmp_path / "take.json").read_text())["ops"]
    assert take and all(op["type"] == "stroke" for op in take)
    app = LiveProcess(
        "disc.mp4", "--ops", "r.json", "--no-browser", "--port", "0", "--duration", "120",
        cwd=tmp_path, command="design",
    )  # fmt: skip
    url = app.url.rstrip("/")
    try:
        assert app.get("/api/motion")["active"] is False  # none seen yet
        app.get("/api/frame.rgba?t=1.99")  # played to its last frame (1.967 s)
        state = app.get("/api/motion")
        assert state["active"] and state["frames"] == 60 and state["strokes"] == take
        at = f"/api/frame.rgba?t={state['t']!r}"
        shown, taken = pixels(app.get(at)), pixels(send(url + at, {**PLAIN, "ops": take}))
        app.get("/api/frame.rgba?t=0.8&w=120")  # scrubbed back: again from the start
        back = app.get("/api/motion")
        app.post("/api/recipe", {**PLAIN, "ops": [WAVE]}, "PUT")
        app.get("/api/frame.rgba?t=1.5&w=120")
        plain = app.get("/api/motion")
    finally:
        assert app.stop() == 0, app.stderr()
    assert np.array_equal(shown, taken)
    assert back["frames"] == 25 and back["t"] == 0.8
    (stroke,) = back["strokes"]
    assert stroke["times"] == take[0]["times"][: len(stroke["times"])]
    assert stroke["times"][-1] <= 0.8 < take[0]["times"][-1]
    assert plain["t"] == back["t"] and plain["frames"] == 25  # no motion: nothing seen


def test_the_page_over_a_video_meters_the_motion_at_the_time_shown(browser, tmp_path):
    encode_clip(disc_clip([DISC], size=(480, 360), seconds=2.0, fps=30), tmp_path / "disc.mp4")
    recipe = tmp_path / "r.json"
    recipe.write_text(json.dumps(RECIPE))
    with designer_page(browser, tmp_path, "disc.mp4", "--ops", recipe) as (page, errors):
        assert page.is_visible("#motion-level") and page.is_visible("#motion-show")
        level = lambda: float(page.get_attribute("#motion-level", "data-level"))  # noqa: E731
        scrub = "(el, t) => { el.value = t; el.dispatchEvent(new Event('input')); }"
        page.locator("#time").evaluate(scrub, 1.0)  # the disc crossing
        wait_for(lambda: level() > 0, "the meter never showed the disc crossing")
        page.check("#motion-show")
        circles = "JSON.parse(document.getElementById('overlay').dataset.circles || '[]')"
        wait_for(lambda: page.evaluate(circles), "no region drawn over the sheet")
        page.locator("#time").evaluate(scrub, 1.9)  # the disc still again
        wait_for(lambda: level() == 0, "the meter never fell back")
        assert errors == []
