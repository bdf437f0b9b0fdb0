"""The recipe's ``motion`` in live sessions (``marblevideo live``): every frame
rendered is seen by the session's one tracker, edits keep it, ``--automation``
writes its strokes into the take as ordinary ``stroke`` ops, and a file played
live gives the tracker what a file render gives it.

The input is a clip made in NumPy (``motion_clips``: a textured disc moving over
a still textured background) and encoded with PyAV as H.264.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from helpers import fresh_renderer
from motion_clips import Disc, disc_clip, line
from motion_video import encode_clip

from marblevideo.design.live import LiveDesign
from marblevideo.live.session import LiveSession
from marblevideo.live.sources import MediaSource
from marblevideo.recipe import parse_recipe

pytestmark = pytest.mark.tier("integration")

D = 80  # the disc's diameter, px
RECIPE = {"marblevideo": 1, "antialias": "none", "motion": {}, "ops": []}


def _clip(seconds: float = 2.0, fps: int = 30):
    """A disc of diameter D crossing a 480x360 frame at 300 px/s from 0.3 s to 1.3 s."""
    disc = Disc(D, (100, 180), line(300), 0.3, 1.3)
    return disc_clip([disc], size=(480, 360), seconds=seconds, fps=fps)


def _follows(stroke: dict, disc: Disc, within: float = max(8, D / 4)) -> None:
    """Each point of ``stroke`` lies ``within`` px (the contract's max(8, D/4)) of
    the disc's centre at its time."""
    for point, t in zip(stroke["points"], stroke["times"], strict=True):
        assert math.dist(point, disc.center(t)) <= within, (point, t, disc.center(t))


def test_a_live_take_holds_motion_strokes_that_follow_the_disc(cli, tmp_path):
    clip = _clip()
    encode_clip(clip, tmp_path / "disc.mp4")
    (tmp_path / "r.json").write_text(json.dumps({**RECIPE, "ops": [WAVE]}))
    done = cli("live", "disc.mp4", "--ops", "r.json", "--automation", "take.json")
    assert done.returncode == 0, done.stderr
    dropped = int(re.search(r"(\d+) source frames dropped", done.stderr).group(1))
    take = json.loads((tmp_path / "take.json").read_text())
    assert "motion" not in take and take["ops"][0] == WAVE
    # the contract's case when every frame was seen; a session that dropped
    # frames (a loaded machine) saw a faster disc, maybe split: it follows it
    strokes = take["ops"][1:]
    assert strokes and all(op["type"] == "stroke" for op in strokes)
    for stroke in strokes:
        _follows(stroke, clip.discs[0], max(8, D / 4) if dropped == 0 else D / 2)
        assert D / 2 <= stroke["width"] <= 3 * D / 2
        last = stroke["times"][-1]
        assert stroke["heal"] == [round(last + 6, 6), round(last + 8, 6)]
    if dropped == 0:  # every frame seen: the contract's timing and one stroke
        assert len(strokes) == 1
        assert strokes[0]["times"][0] <= 0.3 + 0.2 and strokes[0]["times"][-1] >= 1.3 - 0.2
    parse_recipe(take, "take.json")  # renders anywhere: a valid recipe without motion


WAVE = {"type": "wave", "amplitude": 4, "wavelength": 120, "phase": 0, "angle": 90}


class _Unhurried(MediaSource):
    """The file source of ``marblevideo live`` (its decoding, its times), each frame
    published once the session has taken the one before: none is dropped, however
    loaded the machine (a live session that drops frames shows, and takes, fewer)."""

    def publish(self, rgba, ts=None, media_t=None, luma=None) -> None:
        while self.frames.waiting and not self._stop.wait(0.002):
            pass
        super().publish(rgba, ts, media_t, luma)


def test_a_file_played_live_makes_the_take_a_file_render_makes(cli, tmp_path):
    """The tracker sees each frame's decoded luma plane at its time in the file,
    live as in a file render: a session that drops no frame takes what the file
    render takes."""
    path = encode_clip(_clip(), tmp_path / "disc.mp4")
    (tmp_path / "r.json").write_text(json.dumps({**RECIPE, "ops": [WAVE]}))
    renderer = fresh_renderer(loop_walk=True)
    source = _Unhurried(str(path))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    try:
        session.run(10.0)
    finally:
        session.close()
    assert session.source.frames.dropped == 0 and session.frames == 60
    live_take = session.take_document()
    assert len(live_take["ops"]) == 2
    assert renderer.programs.built == 1  # the loop walk's one program, whatever the ops
    done = cli("disc.mp4", "--ops", "r.json", "-o", "out.mp4", "--automation", "take.json", "-q")
    assert done.returncode == 0, done.stderr
    assert json.loads((tmp_path / "take.json").read_text()) == live_take


def _frames(clip):
    for rgb, t in clip:
        yield np.dstack([rgb, np.full(rgb.shape[:2], 255, np.uint8)]), t


def test_an_edit_keeps_the_tracker_and_new_strokes_take_the_new_fields(tmp_path, renderer):
    """Mid-stroke the recipe gets a new gain and an op: the stroke under way goes
    on (with the gain it was made with), a later movement's stroke takes the new one."""
    first = Disc(D, (100, 120), line(300), 0.3, 1.3)
    second = Disc(D, (380, 290), line(300, 180), 1.6, 2.3)
    clip = disc_clip([first, second], size=(480, 360), seconds=2.6, fps=30)
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    source = MediaSource(str(encode_clip(clip, tmp_path / "disc.mp4")))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    design = LiveDesign(session)
    try:
        for n, (rgba, t) in enumerate(_frames(clip)):
            if n == 30:  # t = 1: mid-stroke, more gain and an op
                session.put({**RECIPE, "motion": {"gain": 2.5}, "ops": [WAVE]})
            if n == 36:
                code, body, _ = design.api("GET", "/api/motion", "", None)
                state = json.loads(body)
                assert code == 200 and state["active"] and state["level"] > 0
                (region,) = state["regions"]
                assert math.dist(region["center"], first.center(clip.times[n - 1])) <= 20
                assert [s["drag"] for s in state["strokes"]] == [1.0]
                assert {f["name"] for f in state["fields"]} >= {"gain", "width", "heal"}
                meter = json.loads(design.api("GET", "/api/motion", "shapes=0", None)[1])
                assert (
                    meter["level"] == state["level"] and meter["regions"] == meter["strokes"] == []
                )
            session.show(rgba, 0.0, t)
        take = session.take_document()
    finally:
        session.close()
    assert take["ops"][0] == WAVE and "motion" not in take
    (a, b) = take["ops"][1:]
    assert a["drag"] == 1.0 and a["times"][0] < 1.0 < a["times"][-1]
    assert b["drag"] == 2.5 and b["times"][0] >= 1.6
    _follows(a, first)
    _follows(b, second)


def test_a_recipe_without_motion_leaves_the_frames_and_the_tracker_alone(tmp_path, renderer):
    clip = _clip(seconds=1.0)
    doc = {k: v for k, v in RECIPE.items() if k != "motion"} | {"ops": [WAVE]}
    (tmp_path / "r.json").write_text(json.dumps(doc))
    source = MediaSource(str(encode_clip(clip, tmp_path / "disc.mp4")))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    try:
        for rgba, t in _frames(clip):
            session.show(rgba, 0.0, t)
        assert session.motion.frames == 0 and not session.motion.state()["active"]
        assert session.take_document() == doc
    finally:
        session.close()


def test_a_take_holds_the_controllers_keys_and_the_motion_strokes(tmp_path, renderer):
    """``--automation`` over a recipe with a controller signal and ``motion``: the
    signal becomes keys as before, and the motion strokes are appended."""
    from argparse import Namespace

    from marblevideo.cli.controllers import write_take

    clip = _clip()
    bound = {**WAVE, "amplitude": {"signal": "osc:/a", "range": [0, 8]}}
    (tmp_path / "r.json").write_text(json.dumps({**RECIPE, "ops": [bound]}))
    source = MediaSource(str(encode_clip(clip, tmp_path / "disc.mp4")))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    try:
        for rgba, t in _frames(clip):
            if t == 1.0:
                session.controllers.receive("osc:/a", 0.5, t=1.0)
            session.show(rgba, 0.0, t)
        session.started -= 2.0  # the take's end: two seconds of session
        write_take(
            Namespace(automation=tmp_path / "take.json", overwrite=True, quiet=True), session
        )
    finally:
        session.close()
    take = json.loads((tmp_path / "take.json").read_text())
    wave, stroke = take["ops"]
    assert [k["v"] for k in wave["amplitude"]["keys"]] == [0.0, 4.0]
    assert stroke["type"] == "stroke" and "motion" not in take
    _follows(stroke, clip.discs[0])


def test_a_paused_clock_shows_the_motion_strokes_as_the_frames_made_them(tmp_path, renderer):
    """With the clock paused at 0 (the recipe's ops held still), the strokes are
    moved to it: the disc's path is dragged as the frames made it; the take keeps
    them in the frames' time."""
    clip = _clip()
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    source = MediaSource(str(encode_clip(clip, tmp_path / "disc.mp4")))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    session.control({"paused": True, "time": 0})
    try:
        for rgba, t in _frames(clip):
            out = session.show(rgba, 0.0, t)
            if t == 1.2:
                path = np.abs(out[160:200, 150:330, :3].astype(int) - rgba[160:200, 150:330, :3])
                still = np.abs(out[300:, :, :3].astype(int) - rgba[300:, :, :3])
                assert path.mean() > 8 * max(still.mean(), 0.5), (path.mean(), still.mean())
        take = session.take_document()
    finally:
        session.close()
    assert session.clock.now() == 0
    assert 0.3 <= take["ops"][0]["times"][0] <= 0.5  # the frames' time, not the clock's
