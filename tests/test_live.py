"""``marblevideo live`` end to end: the test pattern, recording, Ctrl-C, the preview server.

Everything runs for real (OpenCL device, PyAV encoder, HTTP on loopback).
"""

from __future__ import annotations

import http.client
import json
import signal
import threading
import time

import av
import numpy as np
import pytest
from helpers import ROOT
from live_helpers import RECIPE, LiveProcess

from marblevideo.errors import UsageError
from marblevideo.live.playback import Clock
from marblevideo.live.session import LiveSession
from marblevideo.live.sources import Latest, TestPattern
from marblevideo.serve.server import Server

pytestmark = pytest.mark.tier("integration")

SWIRL = ROOT / "samples" / "swirl.json"


def _frames(path):
    """(the video stream's time base, [(pts, RGB)]): read while the file is open
    (a stream's fields after its container is closed may be gone)."""
    with av.open(str(path)) as c:
        stream = c.streams.video[0]
        frames = [(f.pts, f.to_ndarray(format="rgb24")) for f in c.decode(stream)]
        return stream.time_base, frames


def test_test_pattern_records_a_valid_file(cli, tmp_path):
    out = tmp_path / "rec.mp4"
    r = cli(
        "live", "test", "--size", "320x180", "--fps", "15", "--ops", SWIRL,
        "--duration", "3", "-o", out,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "wrote" in r.stderr and "live:" in r.stderr
    time_base, frames = _frames(out)
    assert time_base == 1 / 1000 or time_base.denominator % 1000 == 0
    assert len(frames) >= 8
    assert frames[0][1].shape == (180, 320, 3)
    pts = [p for p, _ in frames]
    assert pts == sorted(pts) and len(set(pts)) == len(pts)
    span = float((pts[-1] - pts[0]) * time_base)
    assert 1.5 < span < 3.5  # wall-clock timestamps
    diff = np.abs(frames[0][1].astype(int) - frames[-1][1].astype(int)).mean()
    assert diff > 5  # the pattern moves and the clock runs
    assert not list(tmp_path.glob(".rec.*"))  # no temporary left


def test_sigint_stops_cleanly_and_keeps_the_recording(tmp_path):
    out = tmp_path / "take.mkv"
    live = LiveProcess(
        "--source", "test", "--size", "256x144", "--ops", SWIRL, "-o", out, "--preview",
        "--port", "0", cwd=tmp_path,
    )  # fmt: skip
    try:
        live.wait_stats(lambda s: s["recorded"] >= 10)
    finally:
        rc = live.stop(signal.SIGINT)
    assert rc == 0, live.stderr()
    _, frames = _frames(out)
    assert len(frames) >= 10


def test_bad_recipe_is_refused_before_starting(cli, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"ops": [{"type": "tine", "point": [0, 0], "angle": 0,
                                        "alpha": 1, "lambda": -2}]}))  # fmt: skip
    r = cli("live", "test", "--ops", bad, "--duration", "1", "-o", tmp_path / "x.mp4")
    assert r.returncode == 2
    assert "ops[0].lambda" in r.stderr and r.stderr.count("\n") == 1
    assert not (tmp_path / "x.mp4").exists()


def test_vcam_without_pyvirtualcam_says_how_to_get_one(cli, tmp_path):
    try:
        import pyvirtualcam  # noqa: F401

        pytest.skip("pyvirtualcam is installed here")
    except ImportError:
        pass
    r = cli("live", "test", "--ops", SWIRL, "--vcam", "--duration", "1")
    assert r.returncode == 1
    assert "pip install" in r.stderr and "v4l2loopback" in r.stderr
    assert r.stderr.count("\n") == 1


def test_latest_mailbox_keeps_only_the_newest():
    box = Latest()
    for i in range(5):
        box.put(i)
    assert box.get(0) == 4 and box.dropped == 4
    assert box.get(0.01) is None
    box.put(5)
    assert box.get(0) == 5 and box.dropped == 4


def test_clock_pauses_and_restarts():
    clock = Clock()
    clock.pause()
    a = clock.now()
    time.sleep(0.05)
    assert clock.now() == a
    clock.pause(False)
    time.sleep(0.05)
    assert clock.now() >= a + 0.04
    clock.restart()
    assert clock.now() < 0.02


def test_the_preview_encodes_the_newest_frame_at_its_width():
    """JpegPreview: a frame put is encoded (scaled to the preview's width) under the
    next sequence number; one waited for after the newest times out; close wakes."""
    import cv2

    from marblevideo.live.jpeg import JpegPreview
    from marblevideo.live.meters import RateWindow

    preview, stop, latency = JpegPreview(width=40, quality=90), threading.Event(), RateWindow()
    encoder = threading.Thread(target=preview.run, args=(stop, latency))
    encoder.start()
    try:
        rgba = np.zeros((60, 80, 4), np.uint8)
        rgba[..., 0], rgba[..., 3] = 200, 255  # red
        preview.put(rgba, time.monotonic())
        seq, data, tag, t = preview.latest(0, timeout=5.0)
        assert seq == 1 and tag == 0 and latency.median() is not None
        bgr = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
        assert bgr.shape == (30, 40, 3) and abs(int(bgr[15, 20, 2]) - 200) <= 3
        assert preview.latest(1, timeout=0.05) == (1, None, 0, None)
        preview.close()
        start = time.monotonic()
        assert preview.latest(1, timeout=5.0) == (1, None, 0, None) and time.monotonic() - start < 1
    finally:
        stop.set()
        encoder.join(5)


@pytest.fixture
def session(tmp_path, renderer):
    path = tmp_path / "r.json"
    path.write_text(json.dumps(RECIPE))
    s = LiveSession(path, TestPattern((96, 64), 30), renderer=renderer, jpeg=True, quiet=True)
    yield s
    s.close()


def test_control_validates_requests(session):
    assert session.control({"paused": True})["paused"]
    for bad in (
        {"time": -1},
        {"time": "0.5"},
        {"bypass": "yes"},
        {"jump": True},
        {"param": {"op": 1, "name": "alpha", "value": 3}},  # the old page's overrides
        [],
    ):
        with pytest.raises(UsageError):
            session.control(bad)
    state = session.control({"bypass": True, "mirror": True, "time": 0.5})
    assert (state["bypass"], state["mirror"], state["t"]) == (True, True, 0.5)
    assert set(state) == {"paused", "loop", "bypass", "mirror", "t"}


def test_preview_server_binds_loopback_only(session):
    server = Server(session, 0)
    server.start()
    try:
        host, port = server.address
        assert host == "127.0.0.1"
        assert server.httpd.socket.getsockname()[0] == "127.0.0.1"
        conn = http.client.HTTPConnection(host, port, timeout=5)
        conn.request("GET", "/stats", headers={"Host": "evil.example:80"})
        assert conn.getresponse().status == 403  # DNS rebinding refused
        conn.close()
        conn = http.client.HTTPConnection(host, port, timeout=5)
        conn.request("POST", "/control", body="{}", headers={"Content-Type": "text/plain"})
        assert conn.getresponse().status == 415
        conn.close()
        runner = threading.Thread(target=session.run, kwargs={"duration": 1.5}, daemon=True)
        runner.start()
        conn = http.client.HTTPConnection(host, port, timeout=5)
        deadline = time.monotonic() + 60  # the first frame builds its program (cold cache)
        while True:  # 204: none within the poll's 2 s (the designed answer): ask again
            conn.request("GET", "/frame.jpg")
            r = conn.getresponse()
            if r.status != 204 or time.monotonic() > deadline:
                break
            r.read()
        assert r.status == 200 and r.read()[:2] == b"\xff\xd8"
        seq = int(r.getheader("X-Frame-Seq"))
        conn.request("GET", f"/frame.jpg?after={seq}")  # the next one, waited for
        r = conn.getresponse()
        assert r.status == 200 and r.read()[:2] == b"\xff\xd8"
        assert int(r.getheader("X-Frame-Seq")) > seq
        conn.request("GET", "/")  # a session with no page: none
        r = conn.getresponse()
        assert r.status == 404 and r.read()
        conn.close()
        runner.join(10)
    finally:
        server.stop()


def test_a_poll_with_no_new_frame_gets_no_content(session):
    """The long poll's "none yet" after 2 s is 204 No Content (which a browser does
    not log as an error), with the sequence number it was asked after."""
    server = Server(session, 0)  # the session not running: no frame comes
    server.start()
    try:
        conn = http.client.HTTPConnection(*server.address, timeout=10)
        began = time.monotonic()
        conn.request("GET", "/frame.jpg?after=7")
        r = conn.getresponse()
        assert r.status == 204 and r.read() == b""
        assert time.monotonic() - began >= 1.9  # it waited for a frame first
        assert r.getheader("X-Frame-Seq") == "7" and r.getheader("Content-Length") is None
        conn.request("GET", "/stats")  # the connection is still usable after it
        assert conn.getresponse().status == 200
        conn.close()
    finally:
        server.stop()


def test_the_clock_seeks(session):
    state = session.control({"paused": True, "time": 0.75})
    assert state["t"] == 0.75 and abs(session.clock.now() - 0.75) < 1e-9
    session.control({"time": 0.25})
    assert abs(session.clock.now() - 0.25) < 1e-9


def test_clock_loops_at_the_recipes_end(session):
    assert session.control({"loop": True})["loop"] == 1.0  # RECIPE's last key
    clock = session.clock
    clock.pause()
    clock._origin -= 2.5  # 2.5 s on: 0.5 s into the third pass
    assert abs(clock.now() - 0.5) < 0.05
    assert session.control({"loop": False})["loop"] is None
    assert clock.now() > 2.4


def _api(server, method: str, path: str, body=None) -> tuple[int, dict]:
    host, port = server.address
    conn = http.client.HTTPConnection(host, port, timeout=10)
    data = None if body is None else json.dumps(body)
    conn.request(method, path, body=data, headers={"Content-Type": "application/json"})
    r = conn.getresponse()
    answer = (r.status, json.loads(r.read()))
    conn.close()
    return answer


def test_a_live_recipe_is_edited_through_the_designers_api(session):
    """GET /api/recipe reads the live recipe file, a PUT saves it and the session
    takes it at once; the old page's routes (/params, save-sliders, a control's
    param) are gone, each refused in one line."""
    from marblevideo.design.live import LiveDesign

    path = session.recipe_path
    server = Server(LiveDesign(session), 0)
    server.start()
    try:
        assert _api(server, "GET", "/api/recipe") == (200, RECIPE)
        doc = {**RECIPE, "ops": [RECIPE["ops"][0], {**RECIPE["ops"][1], "alpha": -40}]}
        status, answer = _api(server, "PUT", "/api/recipe", doc)
        assert status == 200 and answer["version"] == 2
        assert json.loads(path.read_text()) == doc
        assert session.recipe.ops[1].params["alpha"].at(0) == -40
        assert _api(server, "GET", "/api/recipe") == (200, doc)
        status, answer = _api(server, "POST", "/api/save-sliders", {})
        assert status == 404 and "no such route" in answer["error"]
        status, answer = _api(server, "POST", "/control", {"param": {"op": 1}})
        assert status == 400 and "PUT /api/recipe" in answer["error"]
        host, port = server.address
        conn = http.client.HTTPConnection(host, port, timeout=10)
        conn.request("GET", "/params")
        assert conn.getresponse().status == 404
        conn.close()
        assert session.recipe_version == 2
    finally:
        server.stop()


def test_the_designers_api_over_a_live_session(session):
    """live --preview serves the designer's page in live mode: /api/info says so and
    gives the source's geometry, /api/ops the types, and a PUT answers as the
    designer's does (or refuses, the file kept)."""
    from marblevideo.design.live import LiveDesign

    path = session.recipe_path
    server = Server(LiveDesign(session), 0)
    server.start()
    try:
        host, port = server.address
        conn = http.client.HTTPConnection(host, port, timeout=10)
        conn.request("GET", "/")
        r = conn.getresponse()
        assert r.status == 200 and b'id="sheet"' in r.read()
        conn.close()
        status, info = _api(server, "GET", "/api/info")
        assert status == 200 and info["mode"] == "live" and info["input"]["kind"] == "live"
        assert (info["size"], info["canvas"], info["scale"], info["ops"]) == (
            [96, 64],
            [96, 64],
            1.0,
            2,
        )
        status, types = _api(server, "GET", "/api/ops")
        assert status == 200 and types["rings"]["layout"] and "comb" in types
        doc = {
            **RECIPE,
            "ops": [
                *RECIPE["ops"],
                {"type": "drop", "center": [9, 9], "radius": 4, "color": "red"},
            ],
        }
        status, answer = _api(server, "PUT", "/api/recipe", doc)
        assert status == 200 and (answer["version"], answer["ops"], answer["mode"]) == (
            2,
            3,
            "live",
        )
        assert json.loads(path.read_text()) == doc and len(session.recipe.ops) == 3
        before = path.read_bytes()
        bad = {**doc, "ops": [{**doc["ops"][2], "radius": 0}]}
        status, answer = _api(server, "PUT", "/api/recipe", bad)
        assert status == 400 and answer["error"].startswith(f"{path}: ops[0].radius")
        assert path.read_bytes() == before and session.recipe_version == 2
    finally:
        server.stop()


def test_a_save_is_known_by_its_stamp_and_another_programs_change_is_seen(session):
    """The page's save takes the recipe it saved, known by the file's stamp (taken
    before the rename), so a change another program makes right after is reloaded."""
    from marblevideo.serve.recipefile import file_stamp, save_stamped

    path = session.recipe_path
    doc = {**RECIPE, "ops": RECIPE["ops"][1:]}
    assert save_stamped(path, doc)[1] == file_stamp(path)
    assert session.put(doc) == 2 and len(session.recipe.ops) == 1
    assert not session.check_reload()  # our own save
    path.write_text(json.dumps(RECIPE))
    assert session.check_reload() and session.recipe_version == 3
    assert len(session.recipe.ops) == 2
