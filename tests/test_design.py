"""``marblevideo design`` without a browser: its HTTP API (urllib) against real
renders and real files, hot reload, and its usage errors. The page itself is
driven in Chromium by tests/test_design_browser.py."""

from __future__ import annotations

import json
import signal
import time
import urllib.error
import urllib.request

import cv2
import numpy as np
import pytest
from helpers import ROOT, one_line
from live_helpers import LiveProcess

from marblevideo import render_image
from marblevideo.recipe.frame import fit

pytestmark = pytest.mark.tier("integration")

COFFEE = ROOT / "samples" / "coffee.jpg"
DROPS = {
    "marblevideo": 1,
    "canvas": [320, 240],
    "background": "#f4f1de",
    "ops": [
        {"type": "drop", "center": [160, 120], "radius": 60, "color": "#1d3557"},
        {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 40, "alpha": 30, "lambda": 8},
    ],
}


def design(tmp_path, *args) -> LiveProcess:
    return LiveProcess(
        *args, "--no-browser", "--port", "0", "--duration", "120", cwd=tmp_path, command="design"
    )


def png(data: bytes) -> np.ndarray:
    """An RGB image from PNG bytes."""
    return cv2.cvtColor(cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR), 4)


def failing(app: LiveProcess, path: str, body, method: str = "PUT") -> tuple[int, dict]:
    with pytest.raises(urllib.error.HTTPError) as exc:
        app.post(path, body, method)
    return exc.value.code, json.loads(exc.value.read())


def wait_info(app: LiveProcess, pred, timeout: float = 10.0) -> dict:
    end = time.monotonic() + timeout
    while not pred(info := app.get("/api/info")):
        assert time.monotonic() < end, info
        time.sleep(0.1)
    return info


def test_api_saves_renders_and_refuses(tmp_path):
    app = design(tmp_path, "--ops", "new.json", "--canvas", "320x240")
    try:
        # a new FILE: a blank sheet of --canvas, no ops, saved at once
        saved = json.loads((tmp_path / "new.json").read_text())
        assert saved == app.get("/api/recipe")
        assert saved["canvas"] == [320, 240] and saved["ops"] == []
        info = app.get("/api/info")
        assert info["size"] == [320, 240] and info["scale"] == 1 and info["offset"] == [0, 0]
        assert info["mode"] == "design"
        # PUT: saved as given, and the frame is the exact render of the main command
        answer = app.post("/api/recipe", DROPS, "PUT")
        assert answer["version"] == info["version"] + 1 and answer["ops"] == 2
        assert json.loads((tmp_path / "new.json").read_text()) == DROPS
        assert app.get("/api/recipe") == DROPS
        expected = render_image(DROPS)[..., :3]
        assert np.array_equal(png(app.get("/api/frame.png")), expected)
        raw = app.get("/api/frame.rgba")  # what the page draws: width, height, RGBA rows
        assert raw[:8] == (320).to_bytes(4, "little") + (240).to_bytes(4, "little")
        pixels = np.frombuffer(raw[8:], np.uint8).reshape(240, 320, 4)
        assert np.array_equal(pixels[..., :3], expected) and (pixels[..., 3] == 255).all()
        # a draft: smaller, not antialiased; hidden ops: only the background
        draft = png(app.get("/api/frame.png?draft=1&w=160"))
        assert draft.shape == (120, 160, 3)
        plain = {**DROPS, "antialias": "none"}
        assert np.array_equal(draft, render_image(plain, size=(160, 120))[..., :3])
        assert (png(app.get("/api/frame.png?ops=")) == [0xF4, 0xF1, 0xDE]).all()
        solo = png(app.get("/api/frame.png?ops=1"))  # a comb alone moves nothing visible
        assert (solo == [0xF4, 0xF1, 0xDE]).all()
        # an op saved hidden is left out of frames and SVG; solo draws it all the same
        comb_only = {**DROPS, "ops": DROPS["ops"][1:]}
        app.post("/api/recipe", comb_only, "PUT")
        comb_svg = app.get("/api/design.svg")
        hidden = {**DROPS, "ops": [{**DROPS["ops"][0], "hidden": True}, DROPS["ops"][1]]}
        assert app.post("/api/recipe", hidden, "PUT")["ops"] == 2
        assert (png(app.get("/api/frame.png")) == [0xF4, 0xF1, 0xDE]).all()
        assert app.get("/api/design.svg") == comb_svg
        drop_only = render_image({**DROPS, "ops": DROPS["ops"][:1]})[..., :3]
        assert np.array_equal(png(app.get("/api/frame.png?ops=0")), drop_only)
        answer = app.post("/api/recipe", DROPS, "PUT")  # back as it was
        # a draft of an unsaved recipe (POST) is rendered, not saved
        moved = {**DROPS, "ops": [{**DROPS["ops"][0], "center": [60, 60]}]}
        req = urllib.request.Request(
            app.url + "api/frame.png",
            data=json.dumps(moved).encode(),
            headers={"Content-Type": "application/json"},
        )
        with urllib.request.urlopen(req) as r:
            assert np.array_equal(png(r.read()), render_image(moved)[..., :3])
        assert json.loads((tmp_path / "new.json").read_text()) == DROPS
        # SVG of the blank sheet's design
        assert app.get("/api/design.svg").startswith(b"<?xml")

        # an invalid recipe: 400, the one-line JSON-path error, nothing saved
        before = (tmp_path / "new.json").read_bytes()
        bad = json.loads(json.dumps(DROPS))
        bad["ops"][1]["lambda"] = -2
        code, error = failing(app, "/api/recipe", bad)
        assert code == 400
        assert error["error"] == "new.json: ops[1].lambda: must be > 0, got -2"
        code, error = failing(app, "/api/recipe", {"ops": [{"type": "drip"}]})
        assert code == 400 and "ops[0].type" in error["error"] and "\n" not in error["error"]
        assert (tmp_path / "new.json").read_bytes() == before
        assert app.get("/api/info")["version"] == answer["version"]
        assert sorted(p.name for p in tmp_path.iterdir()) == ["design.stderr", "new.json"]
        # bad queries, routes and requests
        for query, fault in (("t=x", "t: expected a number"), ("ops=9", "ops: an index")):
            with pytest.raises(urllib.error.HTTPError) as exc:
                app.get(f"/api/frame.png?{query}")
            assert exc.value.code == 400 and fault in json.loads(exc.value.read())["error"]
        assert failing(app, "/api/info", {}, "PUT")[0] == 405
        assert failing(app, "/api/nothing", {}, "PUT")[0] == 404
        req = urllib.request.Request(app.url + "api/recipe", data=b"{}", method="PUT")
        req.add_header("Content-Type", "text/plain")
        with pytest.raises(urllib.error.HTTPError) as exc:
            urllib.request.urlopen(req)
        assert exc.value.code == 415
        req = urllib.request.Request(app.url + "api/recipe", headers={"Host": "example.com"})
        with pytest.raises(urllib.error.HTTPError) as exc:
            urllib.request.urlopen(req)
        assert exc.value.code == 403
        # the page
        assert b'canvas id="sheet"' in app.get("/")
    finally:
        rc = app.stop()
    assert rc == 0
    assert "saved new.json" in app.stderr()


def test_hot_reload_follows_the_file(tmp_path):
    (tmp_path / "r.json").write_text(json.dumps(DROPS))
    app = design(tmp_path, "--ops", "r.json")
    try:
        version = app.get("/api/info")["version"]
        changed = {**DROPS, "background": "#000000"}
        (tmp_path / "r.json").write_text(json.dumps(changed))
        info = wait_info(app, lambda i: i["version"] > version)
        assert app.get("/api/recipe") == changed and info["error"] is None
        assert (png(app.get("/api/frame.png?ops=")) == 0).all()
        # an invalid save on disk is reported; the last good recipe stays
        (tmp_path / "r.json").write_text('{"ops": [}')
        info = wait_info(app, lambda i: i["error"] is not None)
        assert info["error"].startswith("r.json: invalid JSON at line 1")
        assert info["version"] == version + 1
        code, answer = failing(app, "/api/recipe", None, "GET")  # 409: FILE is broken
        assert code == 409 and answer == {**answer, "error": info["error"], "last_good": changed}
        # the page's next good save clears it
        app.post("/api/recipe", DROPS, "PUT")
        assert app.get("/api/info")["error"] is None
        assert json.loads((tmp_path / "r.json").read_text()) == DROPS
    finally:
        assert app.stop(signal.SIGTERM) == 0
    # the refused save is said once on stderr, as live says it
    said = [line for line in app.stderr().splitlines() if "invalid JSON" in line]
    assert said == [f"marblevideo: {info['error']}"], app.stderr()
    assert said[0].endswith("(keeping the previous recipe)")


def test_over_a_photo_the_canvas_sits_in_the_frame(tmp_path):
    """--canvas 100x100 over a 600x400 photo: scale 4, centred (the contract's geometry)."""
    app = design(tmp_path, COFFEE, "--ops", "photo.json", "--canvas", "100x100")
    try:
        info = app.get("/api/info")
        assert info["input"] == {"kind": "image", "name": str(COFFEE), "duration": 0.0}
        s, dx, dy = fit((100, 100), 600, 400)
        assert info["size"] == [600, 400] and info["canvas"] == [100, 100]
        assert (info["scale"], info["offset"]) == (s, [dx, dy]) == (4.0, [100.0, 0.0])
        recipe = {"canvas": [100, 100], "ops": [{"type": "vortex", "center": [50, 50],
                                                 "alpha": 80, "lambda": 20}]}  # fmt: skip
        app.post("/api/recipe", recipe, "PUT")
        image = cv2.cvtColor(cv2.imread(str(COFFEE)), cv2.COLOR_BGR2RGBA)
        assert np.array_equal(png(app.get("/api/frame.png")), render_image(recipe, image)[..., :3])
        code, error = failing(app, "/api/design.svg", {}, "GET")
        assert code == 400 and "blank sheet" in error["error"]
    finally:
        assert app.stop() == 0


def test_a_video_is_scrubbed(tmp_path):
    app = design(tmp_path, ROOT / "samples" / "coffee.mp4", "--ops", "v.json")
    try:
        info = app.get("/api/info")
        assert info["input"]["kind"] == "video" and info["input"]["duration"] > 0.5
        assert "canvas" not in app.get("/api/recipe")  # the input's size
        first, later = (png(app.get(f"/api/frame.png?t={t}")) for t in (0, 0.5))
        assert np.abs(first.astype(int) - later).mean() > 1
        assert np.array_equal(first, png(app.get("/api/frame.png?t=0")))
    finally:
        assert app.stop() == 0


@pytest.mark.parametrize(
    "args, fault",
    [
        (["--ops", "r.json", "--canvas", "10"], "--canvas: expected WxH"),
        (["--ops", "exists.json", "--canvas", "10x10"], "--canvas: exists.json exists"),
        (["--ops", "bad.json"], "bad.json: ops[0].radius: must be > 0, got 0"),
        (["--ops", "nocanvas.json"], "nocanvas.json: canvas: a blank-sheet design needs"),
        (["--ops", "no/such/r.json"], "folder no/such does not exist"),
        (["missing.png", "--ops", "r.json"], "missing.png: no such file"),
        (["--ops", "r.json", "--port", "70000"], "--port: must be 0..65535"),
        (["--ops", "r.json", "--size", "64x48"], "--size: applies to a live source only"),
        (["--ops", "r.json", "--duration", "0"], "--duration: must be > 0"),
    ],
)
def test_usage_errors_are_one_line(cli, tmp_path, args, fault):
    (tmp_path / "exists.json").write_text(json.dumps(DROPS))
    bad = {**DROPS, "ops": [{"type": "drop", "center": [1, 1], "radius": 0, "color": "red"}]}
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    (tmp_path / "nocanvas.json").write_text(json.dumps({"ops": []}))
    before = sorted(p.name for p in tmp_path.iterdir())
    proc = cli("design", *args, "--no-browser")
    assert proc.returncode == 2
    assert fault in one_line(proc)
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing created
