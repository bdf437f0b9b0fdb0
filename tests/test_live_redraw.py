"""A new recipe between captured frames (the designer's preview, a save) marbles
the last captured frame again at once for the preview's JPEG
(:mod:`marblevideo.live.redraw`), and only for it: the frames shown to the
outputs, the rates and the motion tracker see each captured frame once.

The source is the real test pattern at 0.2 fps (a frame every 5 s), so a JPEG
that shows a preview before the next capture can only be a redraw."""

from __future__ import annotations

import json
import threading
import time

import cv2
import numpy as np
import pytest

from marblevideo.design.live import LiveDesign
from marblevideo.live.redraw import LastFrame
from marblevideo.live.session import LiveSession
from marblevideo.live.sources import TestPattern

pytestmark = pytest.mark.tier("integration")

DROP = {"type": "drop", "center": [48, 32], "radius": 20, "color": "#e63946"}
RECIPE = {"marblevideo": 1, "antialias": "none", "ops": []}


def _running(tmp_path, renderer, recipe):
    (tmp_path / "r.json").write_text(json.dumps(recipe))
    source = TestPattern((96, 64), 0.2)
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, jpeg=True, quiet=True)
    runner = threading.Thread(target=session.run, kwargs={"duration": 30}, daemon=True)
    runner.start()
    return session, runner


def _jpeg(session, after: int, tag: int | None = None, timeout: float = 20.0):
    """The first JPEG newer than ``after`` (with ``tag``, when given): (seq, RGB, tag)."""
    while True:
        seq, data, got, _ = session.latest_jpeg(after, timeout)
        assert data is not None, "no JPEG came"
        if tag is None or got == tag:
            rgb = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)[..., ::-1]
            return seq, rgb, got
        after = seq


def _preview(session, doc) -> int:
    version = session.file.snapshot()[2]
    body = json.dumps({"recipe": doc, "version": version}).encode()
    code, answer, _ = LiveDesign(session).api("PUT", "/api/preview", "", body)
    assert code == 200, answer
    return json.loads(answer)["serial"]


def test_a_preview_is_shown_on_the_last_captured_frame_before_the_next(tmp_path, renderer):
    session, runner = _running(tmp_path, renderer, RECIPE)
    try:
        seq, before, tag = _jpeg(session, 0)
        assert tag == 0 and session.frames == 1
        serial = _preview(session, {**RECIPE, "ops": [DROP]})
        seq, shown, tag = _jpeg(session, seq, serial)
        stats = session.stats()
        # no frame was captured since: this JPEG is the first frame marbled again
        assert (stats["frames"], stats["redrawn"]) == (1, 1)
        assert np.abs(shown.astype(int) - before.astype(int)).max() > 100  # the red drop
        # its way through the session, in order (wall-clock ms): GET /stats
        times = stats["preview_times"][str(serial)]
        steps = [times[k] for k in ("received", "start", "rendered", "ready")]
        assert steps == sorted(steps) and steps[-1] - steps[0] < 20000, times
        red = shown[32, 48]
        assert red[0] > 180 and red[1] < 110 and red[2] < 110, red
        # a save of the same recipe: shown at once too, no preview tag
        session.put({**RECIPE, "ops": [DROP]})
        seq, saved, tag = _jpeg(session, seq)
        assert tag == 0 and session.frames == 1 and session.stats()["redrawn"] == 2
        assert np.abs(saved.astype(int) - shown.astype(int)).mean() < 4
    finally:
        session.close()
        runner.join(10)


def test_a_redraw_is_not_seen_by_the_motion_nor_the_take(tmp_path, renderer):
    """With ``motion``, the tracker sees each captured frame once: a preview's
    redraw leaves its frame count and the ``--automation`` take as they were."""
    session, runner = _running(tmp_path, renderer, {**RECIPE, "motion": {}})
    try:
        seq, _, _ = _jpeg(session, 0)
        seen, take = session.motion.frames, session.take_document()
        assert seen == 1
        serial = _preview(session, {**RECIPE, "motion": {}, "ops": [DROP]})
        _, shown, _ = _jpeg(session, seq, serial)
        assert session.frames == 1 and session.stats()["redrawn"] == 1
        assert session.motion.frames == seen and session.take_document() == take
        assert shown[32, 48][0] > 180
    finally:
        session.close()
        runner.join(10)


def test_a_redraw_waits_where_it_would_cost_a_captured_frame():
    last = LastFrame(30.0)
    assert not last.allows(0.0, waiting=False)  # nothing captured yet
    last.captured(np.zeros((4, 4, 4), np.uint8), 10.0, 0.010)
    assert last.allows(10.011, waiting=False)  # idle: the next frame comes at 10.033
    assert not last.allows(10.011, waiting=True)  # a captured frame first
    assert last.allows(10.050, waiting=False)  # the next frame (come) right after it
    assert not last.allows(10.060, waiting=False)  # would end after the frame after it came
    last.captured(last.rgba, 10.0, 0.030)  # slow renders: still while the loop idles
    assert last.allows(10.031, waiting=False)  # ends at 10.061, before 10.0667
    assert not last.allows(10.040, waiting=False)
    slow = LastFrame(2.0)
    slow.captured(last.rgba, 10.0, 0.030)
    assert slow.allows(10.4, waiting=False)


def test_previews_during_a_running_source_are_redrawn_and_no_frame_is_lost(tmp_path, renderer):
    """A source at 20 fps, a preview every 30 ms for 2 s (a drag): the idle loop
    redraws for them, and each captured frame is shown once: the frames shown and
    those the source dropped add up to those it captured, none twice."""
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    source = TestPattern((96, 64), 20.0)
    session = LiveSession(tmp_path / "r.json", source, renderer=renderer, jpeg=True, quiet=True)
    runner = threading.Thread(target=session.run, kwargs={"duration": 30}, daemon=True)
    runner.start()
    try:
        _jpeg(session, 0)
        for k in range(66):
            _preview(session, {**RECIPE, "ops": [{**DROP, "center": [20 + k % 60, 32]}]})
            time.sleep(0.03)
        session.stop_event.set()
        runner.join(10)
        stats = session.stats()
        assert stats["redrawn"] > 0
        assert session.frames + stats["dropped"] == source._seq, (session.frames, stats)
    finally:
        session.close()
        runner.join(10)
