"""``marblevideo live --preview``: a stroke drawn on the page moves the live
frames' ink as it is drawn, before the mouse is released, and is saved on
release with its times on the live clock; a comb dragged shows in the live
frames before release too, and each live frame that first shows a preview
answers the pointer input it was made after (the latency the benchmark
reads). Real Chromium (Playwright) over a still photo looped
(``samples/coffee.jpg --loop``, 600x400: the canvas), the clock running.
Skipped, with the reason, without Playwright or Chromium."""

from __future__ import annotations

import time

import numpy as np
import pytest
from live_helpers import live_designer, live_settled, wait_for

pytestmark = pytest.mark.tier("integration")

EMPTY = {"marblevideo": 1, "ops": []}

#: The stroke drawn, in frame pixels: left to right across the middle.
PATH = [(120 + 9 * k, 200 + 30 * np.sin(k / 6)) for k in range(41)]


def _near_path(image: np.ndarray, scale: float) -> np.ndarray:
    """The pixels of ``image`` (a shot of the sheet) within 12 frame px of the
    path's first half."""
    h, w = image.shape[:2]
    yy, xx = np.mgrid[0:h, 0:w] / scale
    mask = np.zeros((h, w), bool)
    for x, y in PATH[:20]:
        mask |= (xx - x) ** 2 + (yy - y) ** 2 < 144
    return image[mask]


def test_a_stroke_moves_the_live_ink_as_it_is_drawn(browser, tmp_path):
    with live_designer(browser, tmp_path, EMPTY) as (live, page, errors, saved):
        box = page.locator("#overlay").bounding_box()
        scale = box["width"] / 600  # the shot's pixels per frame pixel

        def client(px: float, py: float) -> tuple[float, float]:
            return box["x"] + px * box["width"] / 600, box["y"] + py * box["height"] / 400

        before = live_settled(page, live)
        page.keyboard.press("p")  # the stroke tool's key
        assert page.evaluate("designer.state.tool") == "stroke"
        clock = live.get("/stats")["t"]
        page.mouse.move(*client(*PATH[0]))
        pressed = time.monotonic()
        page.mouse.down()
        for p in PATH[1:21]:
            page.mouse.move(*client(*p))
            time.sleep(0.03)
        # mid-drag: nothing saved, and the live frames show the stroke so far
        mid = live_settled(page, live)
        assert saved() == []
        moved = np.abs(_near_path(mid, scale) - _near_path(before, scale)).mean()
        far = np.abs(mid[-40:, :] - before[-40:, :]).mean()  # the bottom rows: untouched
        assert moved > 8 and far < 2, (moved, far)
        for p in PATH[21:]:
            page.mouse.move(*client(*p))
            time.sleep(0.03)
        page.mouse.up()
        drew = time.monotonic() - pressed
        (stroke,) = wait_for(saved, "the stroke is saved")
        times = stroke["times"]
        assert stroke["type"] == "stroke" and len(times) == len(stroke["points"]) == len(PATH)
        assert times == sorted(times)
        assert abs(times[0] - clock) < 1.0  # the live clock at the press
        assert 0.5 * drew < times[-1] - times[0] < drew + 0.2  # the drag's span
        # the preview is gone, the saved stroke is shown: the path's ink stays moved
        after = live_settled(page, live)
        assert np.abs(_near_path(after, scale) - _near_path(before, scale)).mean() > 8
        page.close()
        assert errors == []


def test_a_comb_shows_in_the_live_frames_while_dragged(browser, tmp_path):
    with live_designer(browser, tmp_path, EMPTY) as (live, page, errors, saved):
        box = page.locator("#overlay").bounding_box()
        before = live_settled(page, live)
        page.evaluate("designer.setTool('comb')")
        first = page.evaluate("window.marbleFrames.length")
        page.mouse.move(box["x"] + 0.2 * box["width"], box["y"] + 0.5 * box["height"])
        page.mouse.down()
        y = box["y"] + 0.5 * box["height"]
        for k in range(1, 16):
            page.mouse.move(box["x"] + (0.2 + 0.03 * k) * box["width"], y)
            time.sleep(0.05)
        mid = live_settled(page, live)
        assert saved() == []
        assert np.abs(mid.astype(float) - before).mean() > 2  # the comb shows unsaved
        frames = page.evaluate("window.marbleFrames")[first:]
        answering = [f for f in frames if f["kind"] == "live" and f["input"] is not None]
        assert answering, "no live frame answered a pointer input"
        assert all(f["drawnAt"] >= f["inputAt"] for f in answering)
        assert len({f["input"] for f in answering}) == len(answering)  # each answered once
        page.mouse.up()
        (comb,) = wait_for(saved, "the comb is saved")
        assert comb["type"] == "comb"
        page.close()
        assert errors == []
