"""The live page's motion panel (``marblevideo live --preview``), driven in a real
headless Chromium (Playwright): the overlay's circles are where the disc is, the
fields edit the recipe's ``motion`` block (a refusal shown), the meter moves.

The source is a clip made in NumPy (``motion_clips``: a textured disc crossing a
still textured background, then still), encoded with PyAV and played ``--loop``.
Skipped, with the reason, when Playwright or Chromium is missing.
"""

from __future__ import annotations

import json
import math

import pytest
from live_helpers import REFUSED, LiveProcess, designer_page, wait_for, watched_page
from motion_clips import Disc, disc_clip, line
from motion_video import encode_clip

pytestmark = pytest.mark.tier("integration")

D = 80
PERIOD = 2.0  # the clip's length: a looped pass starts one frame after the last


def _circles(page) -> tuple[list, float | None]:
    """The circles the overlay drew ([x, y, r] in the sheet's device pixels) and their
    frame's time."""
    data = page.evaluate("({...document.getElementById('overlay').dataset})")
    t = data.get("motionT")
    return json.loads(data.get("circles") or "[]"), (float(t) if t else None)


def _alpha(page, x: float, y: float) -> int:
    return page.evaluate(
        """([x, y]) => document.getElementById('overlay').getContext('2d')
            .getImageData(Math.floor(x), Math.floor(y), 1, 1).data[3]""",
        [x, y],
    )


def test_the_motion_panel_shows_edits_and_meters_the_motion(browser, tmp_path):
    disc = Disc(D, (100, 180), line(300), 0.3, 1.3)
    clip = disc_clip([disc], size=(480, 360), seconds=PERIOD, fps=30)
    encode_clip(clip, tmp_path / "disc.mp4")
    recipe = tmp_path / "live.json"
    recipe.write_text(json.dumps({"marblevideo": 1, "antialias": "none", "motion": {}, "ops": []}))
    live = LiveProcess(
        "disc.mp4", "--loop", "--ops", recipe, "--preview", "--port", "0", "--duration", "120",
        cwd=tmp_path,
    )  # fmt: skip
    saved = lambda: json.loads(recipe.read_text())  # noqa: E731
    try:
        page, errors = watched_page(browser, live.url, "body[data-ready='1'][data-mode='live']")
        assert page.is_visible("#motion-panel") and page.is_checked("#motion-on")
        assert page.get_attribute("#motion-gain", "placeholder") == "1"
        # the meter moves: motion while the disc crosses, none while it is still
        level = lambda: float(page.get_attribute("#motion-level", "data-level"))  # noqa: E731
        wait_for(lambda: level() > 0, "the meter never showed motion")
        wait_for(lambda: level() == 0, "the meter never fell back")
        # no circle until shown; then circles where the disc is at their frame's time
        assert _circles(page)[0] == []
        page.check("#motion-show")

        def on_the_disc():
            circles, t = _circles(page)
            if not circles or t is None:
                return None
            (x, y, r), centre = circles[0], disc.center(t % PERIOD)
            # the overlay has the sheet's device pixels; the canvas is the frame's pixels
            k = page.evaluate("document.getElementById('overlay').width") / 480
            at = page.evaluate("(c) => designer.toPixel(c)", list(centre))
            if math.dist((x, y), at) > k * (max(8, D / 4) + 1):
                return None  # (a frame whose time and circles were read apart): the next one
            return x, y, r / k

        x, y, r = wait_for(on_the_disc, "no circle over the moving disc")
        assert D / 4 <= r <= D
        page.uncheck("#motion-show")
        k = page.evaluate("document.getElementById('overlay').width") / 480
        assert _circles(page)[0] == [] and _alpha(page, x + r * k, y) == 0

        # the fields edit the recipe's motion block; a refusal is shown and undone
        page.fill("#motion-gain", "2.5")
        page.press("#motion-gain", "Enter")
        wait_for(lambda: saved().get("motion") == {"gain": 2.5}, "gain not saved")
        page.fill("#motion-width-0", "30")  # a pair's other side: its default
        page.press("#motion-width-0", "Enter")
        wait_for(lambda: saved()["motion"].get("width") == [30, 200], "width not saved")
        page.wait_for_function("designer.state.doc.motion.width !== undefined")
        page.fill("#motion-width-1", "150")
        page.press("#motion-width-1", "Enter")
        wait_for(lambda: saved()["motion"].get("width") == [30, 150], f"width not saved: {saved()}")
        page.fill("#motion-max_strokes", "99")
        page.press("#motion-max_strokes", "Enter")
        page.wait_for_selector("#error:has-text('motion.max_strokes')")
        page.wait_for_function("document.getElementById('motion-max_strokes').value === ''")
        assert "max_strokes" not in saved()["motion"]
        page.uncheck("#motion-on")
        wait_for(lambda: "motion" not in saved(), "motion not removed")
        page.wait_for_selector("#motion-gain:disabled")
        wait_for(lambda: live.get("/api/motion")["active"] is False, "motion still active")
        page.check("#motion-on")
        wait_for(lambda: saved().get("motion") == {}, "motion not added back")
        assert [e for e in errors if e != REFUSED] == []
        page.close()
    finally:
        assert live.stop() == 0


def test_the_designer_edits_the_motion_block_without_meter(browser, tmp_path):
    """In design mode over a blank sheet the panel edits the block (its renders
    have no motion strokes: they come from a live source's or a video's frames,
    tests/test_design_motion.py), with no meter and no overlay."""
    recipe = tmp_path / "d.json"
    recipe.write_text(json.dumps({"marblevideo": 1, "canvas": [320, 240], "ops": []}))
    saved = lambda: json.loads(recipe.read_text())  # noqa: E731
    with designer_page(browser, tmp_path, "--ops", recipe) as (page, errors):
        assert page.is_visible("#motion-panel") and not page.is_checked("#motion-on")
        assert not page.is_visible("#motion-level") and not page.is_visible("#motion-show")
        page.wait_for_selector("#motion-heal:disabled")
        page.check("#motion-on")
        wait_for(lambda: saved().get("motion") == {}, "motion not added")
        page.fill("#motion-heal", "3")
        page.press("#motion-heal", "Enter")
        wait_for(lambda: saved().get("motion") == {"heal": 3}, "heal not saved")
        assert errors == []
