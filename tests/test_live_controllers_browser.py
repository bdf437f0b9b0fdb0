"""The live page's signal bindings in a real headless Chromium (Playwright):
``marblevideo live --preview --osc`` over a looped photo (every frame the same
unless a controller moves), OSC over UDP on loopback. Skipped, with the reason,
when Playwright or Chromium is missing."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from helpers import ROOT
from live_helpers import LiveProcess, frame_diff, live_settled, wait_for, watched_page
from pythonosc.udp_client import SimpleUDPClient

pytestmark = pytest.mark.tier("integration")

RECIPE = {
    "marblevideo": 1,
    "antialias": "none",
    "edges": "mirror",
    "ops": [{"type": "vortex", "center": [300, 200], "alpha": 40, "lambda": 80}],
}


def _meter(page, name: str, y: float) -> None:
    page.wait_for_function(
        f"(() => {{ const m = document.getElementById('m-{name}');"
        f" return m && Math.abs(Number(m.dataset.y) - {y}) < 1e-3; }})()",
        timeout=20000,
    )


def test_a_slider_bound_to_an_osc_address_moves_with_it(browser, tmp_path):
    recipe = tmp_path / "live.json"
    recipe.write_text(json.dumps(RECIPE))
    live = LiveProcess(
        ROOT / "samples" / "coffee.jpg", "--loop", "--ops", recipe, "--preview", "--port", "0",
        "--osc", "0", "--duration", "120", cwd=tmp_path,
    )  # fmt: skip
    saved = lambda: json.loads(recipe.read_text())["ops"][0]  # noqa: E731
    try:
        client = SimpleUDPClient("127.0.0.1", int(live.proc.stdout.readline().rsplit(":", 1)[1]))
        page, errors = watched_page(browser, live.url, "body[data-ready='1'][data-mode='live']")
        page.click("#op-0 .name")
        page.wait_for_selector("#bind-alpha")
        before = live_settled(page, live)

        # bind alpha to a typed OSC address: saved into the recipe with the slider's
        # range, off at 0 (a symmetric range binds 0..max: a fader at 0 is at rest)
        page.once("dialog", lambda d: d.accept("/swirl"))
        page.select_option("#bind-alpha", "osc")
        wait_for(lambda: isinstance(saved()["alpha"], dict), "the binding is saved")
        bound = saved()["alpha"]
        assert bound["signal"] == "osc:/swirl" and bound["range"][0] == 0 < 40 < bound["range"][1]
        page.wait_for_selector("#m-alpha")
        _meter(page, "alpha", 0.0)

        # OSC moves the meter and the frame
        client.send_message("/swirl", 1.0)
        _meter(page, "alpha", 1.0)
        moved = live_settled(page, live)
        assert frame_diff(before, moved) > 5
        client.send_message("/swirl", 0.25)
        _meter(page, "alpha", 0.25)
        assert frame_diff(moved, live_settled(page, live)) > 2

        # learn: the next control moved is bound
        page.select_option("#bind-lambda", "learn")
        page.wait_for_function("document.getElementById('status').textContent.startsWith('learn')")
        client.send_message("/knob/2", 0.5)
        wait_for(lambda: isinstance(saved()["lambda"], dict), "the learned binding is saved")
        assert saved()["lambda"]["signal"] == "osc:/knob/2"
        assert saved()["lambda"]["range"][0] > 0  # a positive parameter's range
        page.wait_for_selector("#m-lambda")
        _meter(page, "lambda", 0.5)

        # unbound: the value it has now, as a constant
        page.select_option("#bind-alpha", "")
        wait_for(lambda: not isinstance(saved()["alpha"], dict), "unbound")
        lo, hi = bound["range"]
        assert abs(saved()["alpha"] - (lo + 0.25 * (hi - lo))) < 0.01
        stats = live.get("/stats")["controllers"]
        assert stats["dropped"] == 0 and stats["messages"] == 3
        assert errors == []
    finally:
        live.stop()


def test_the_designer_over_a_live_source_takes_osc(browser, tmp_path):
    recipe = tmp_path / "design.json"
    recipe.write_text(json.dumps({
        "marblevideo": 1, "canvas": [320, 240], "antialias": "none",
        "ops": [{"type": "drop", "center": [160, 120], "color": "#ff00ff",
                 "radius": {"signal": "osc:/size", "range": [1, 100]}}],
    }))  # fmt: skip
    design = LiveProcess(
        "test", "--size", "320x240", "--ops", recipe, "--osc", "0", "--no-browser",
        "--port", "0", "--duration", "120", cwd=tmp_path, command="design",
    )  # fmt: skip
    try:
        client = SimpleUDPClient("127.0.0.1", int(design.proc.stdout.readline().rsplit(":", 1)[1]))
        ring = lambda: _shot_png(design.get("/api/frame.png?t=1"))[120, 160 + 50]  # noqa: E731
        assert tuple(ring()) != (255, 0, 255)  # radius 1: the pattern shows there
        page, errors = watched_page(browser, design.url, "body[data-ready='1']")
        page.click("#op-0 .name")
        page.wait_for_selector("#m-radius")
        client.send_message("/size", 1.0)
        _meter(page, "radius", 1.0)
        assert tuple(ring()) == (255, 0, 255)  # radius 100: the drop covers it
        assert errors == []
    finally:
        design.stop()


def _shot_png(data: bytes) -> np.ndarray:
    """A PNG as an RGB array."""
    bgr = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
