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


def _follows(stroke: dict, disc: Disc) -> None:
    """Each point of ``stroke`` lies within max(8, D/4) px of the disc's centre at its time."""
    for point, t in zip(stroke["points"], stroke["times"], strict=True):
        assert math.dist(point, disc.center(t)) <= max(8, D / 4), (point, t, disc.center(t))


def test_a_live_take_holds_motion_strokes_that_follow_the_disc(cli, tmp_path):
    clip = _clip()
    encode_clip(clip, tmp_path / "disc.mp4")
    (tmp_path / "r.json").write_text(json.dumps({**RECIPE, "ops": [WAVE]}))
    done = cli("live", "disc.mp4", "--ops", "r.json", "--automation", "take.json", "-q")
    assert done.returncode == 0, done.stderr
    take = json.loads((tmp_path / "take.json").read_text())
    assert "motion" not in take and take["ops"][0] == WAVE
    strokes = take["ops"][1:]
    assert len(strokes) == 1 and strokes[0]["type"] == "stroke"
    stroke = strokes[0]
    _follows(stroke, clip.discs[0])
    assert stroke["times"][0] <= 0.3 + 0.2 and stroke["times"][-1] >= 1.3 - 0.2
    assert D / 2 <= stroke["width"] <= 3 * D / 2
    assert stroke["heal"] == [round(stroke["times"][-1] + 6, 6), round(stroke["times"][-1] + 8, 6)]
    parse_recipe(take, "take.json")  # renders anywhere: a valid recipe without motion


WAVE = {"type": "wave", "amplitude": 4, "wavelength": 120, "phase": 0, "angle": 90}


def test_a_file_played_live_makes_the_take_a_file_render_makes(cli, tmp_path):
    """The tracker sees each frame's decoded luma plane at its time in the file,
    live as in a file render. The live session must drop no frame for its tracker
    to see every frame, so the clip is small and at 15 fps (a session that drops
    frames makes fewer points: BENCHMARKS.md says when a machine keeps up)."""
    path = encode_clip(_clip(fps=15), tmp_path / "disc.mp4", fps=15)
    (tmp_path / "r.json").write_text(json.dumps({**RECIPE, "ops": [WAVE]}))
    renderer = fresh_renderer(loop_walk=True)
    source = MediaSource(str(path))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    try:
        session.run(10.0)
    finally:
        session.close()
    assert session.source.frames.dropped == 0, "the session dropped frames: too slow to compare"
    assert session.frames == 30
    live_take = session.take_document()
    assert len(live_take["ops"]) == 2
    assert renderer.programs.built == 1  # the loop walk's one program, whatever the ops
    done = cli("disc.mp4", "--ops", "r.json", "-o", "out.mp4", "--automation", "take.json", "-q")
    assert done.returncode == 0, done.stderr
    assert json.loads((tmp_path / "take.json").read_text()) == live_take


def _frames(clip):
    for rgb, t in clip:
        yield np.dstack([rgb, np.full(rgb.shape[:2], 255, np.uint8)]), t


def test_an_edit_keeps_the_tracker_and_takes_the_new_fields(tmp_path, renderer):
    clip = _clip()
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    source = MediaSource(str(encode_clip(clip, tmp_path / "disc.mp4")))
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, quiet=True)
    design = LiveDesign(session)
    try:
        for n, (rgba, t) in enumerate(_frames(clip)):
            if t == 1.0:  # mid-stroke: more gain, an op, and the motion goes on
                session.put({**RECIPE, "motion": {"gain": 2.5}, "ops": [WAVE]})
            if t == 1.2:
                code, body, _ = design.api("GET", "/api/motion", "", None)
                state = json.loads(body)
                assert code == 200 and state["active"] and state["level"] > 0
                (region,) = state["regions"]
                assert math.dist(region["center"], clip.discs[0].center(clip.times[n - 1])) <= 20
                assert [s["drag"] for s in state["strokes"]] == [2.5]
                assert {f["name"] for f in state["fields"]} >= {"gain", "width", "heal"}
            session.show(rgba, 0.0, t)
        take = session.take_document()
    finally:
        session.close()
    (stroke,) = take["ops"][1:]
    assert stroke["drag"] == 2.5 and stroke["times"][0] < 1.0 < stroke["times"][-1]
    _follows(stroke, clip.discs[0])
    assert take["ops"][0] == WAVE and "motion" not in take


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
