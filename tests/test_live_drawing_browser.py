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


def _comb_held(page, live) -> tuple[np.ndarray, np.ndarray, list[dict]]:
    """A comb pressed at the sheet's left and dragged right, the button still
    held: the sheet before, the sheet once the session's frames show the comb,
    and the frames drawn since the press."""
    box = page.locator("#overlay").bounding_box()
    before = live_settled(page, live)
    page.evaluate("designer.setTool('comb')")
    first = page.evaluate("window.marbleFrames.length")
    y = box["y"] + 0.5 * box["height"]
    page.mouse.move(box["x"] + 0.2 * box["width"], y)
    page.mouse.down()
    for k in range(1, 16):
        page.mouse.move(box["x"] + (0.2 + 0.03 * k) * box["width"], y)
        time.sleep(0.05)
    mid = live_settled(page, live)
    return before, mid, page.evaluate("window.marbleFrames")[first:]


def test_a_comb_shows_in_the_live_frames_while_dragged(browser, tmp_path):
    with live_designer(browser, tmp_path, EMPTY) as (live, page, errors, saved):
        before, mid, frames = _comb_held(page, live)
        assert saved() == []
        assert np.abs(mid.astype(float) - before).mean() > 2  # the comb shows unsaved
        live = [f for f in frames if f["kind"] in ("live", "live-warp")]  # the session's, or warped
        answering = [f for f in live if f["input"] is not None]
        assert answering, "no live frame answered a pointer input"
        assert all(f["drawnAt"] >= f["inputAt"] for f in answering)
        assert len({f["input"] for f in answering}) == len(answering)  # each answered once
        page.mouse.up()
        (comb,) = wait_for(saved, "the comb is saved")
        assert comb["type"] == "comb"
        page.close()
        assert errors == []


#: From now on, each frame drawn that is the page's warp of a live frame and
#: answers an input is kept as ``window.__snap`` as it is recorded (the newest
#: such): {input, png (what the sheet shows then)}, so no later frame can come
#: in between.
KEEP_WARPS = """() => { window.__snap = null; const a = window.marbleFrames, push = a.push.bind(a);
  a.push = (f) => { const n = push(f);
    if (f.kind === 'live-warp' && f.input !== null) {
      const d = designer.sheetPixels(), c = document.createElement('canvas');
      c.width = d.width; c.height = d.height; c.getContext('2d').putImageData(d, 0, 0);
      window.__snap = {input: f.input, png: c.toDataURL('image/png')};
    }
    return n; }; }"""


def _warped_then_settled(page, live, move) -> tuple[dict, np.ndarray, np.ndarray]:
    """After the session shows the gesture so far: ``move()``, then the page's
    frame that answered the last input of it (the newest live frame warped on
    the page to the gesture as moved: {input}, and its pixels) and what the sheet
    shows once the session's own frames show the gesture as moved (both RGB).
    Fails when a frame of the session answered that input first."""
    from sheet_support import decode_png

    live_settled(page, live)
    page.evaluate(KEEP_WARPS)
    move()
    last = page.evaluate("designer.newestInput().input")
    page.wait_for_function(
        f"window.marbleFrames.some((f) => f.input !== null && f.input >= {last})", timeout=20000
    )
    warped = page.evaluate("window.__snap")
    assert warped is not None and warped["input"] >= last, (warped and warped["input"], last)
    settled = live_settled(page, live)[:, :, ::-1]  # (BGR shot)
    return warped, decode_png(warped["png"]), settled.astype(np.uint8)


def _agree(a: np.ndarray, b: np.ndarray, levels: int = 16) -> float:
    h, w = min(a.shape[0], b.shape[0]), min(a.shape[1], b.shape[1])
    diff = np.abs(a[:h, :w].astype(int) - b[:h, :w].astype(int)).max(axis=2)
    return float((diff <= levels).mean())


@pytest.mark.parametrize("tool", ["comb", "stroke", "drop"])
def test_the_page_warps_the_newest_live_frame_to_the_gesture_at_once(browser, tmp_path, tool):
    """Mid-gesture the page answers a pointer move itself: the newest live frame
    (which shows the gesture as it was) warped to the gesture as it is now, drawn
    before the session's frame of it comes, and agreeing with that frame."""
    with live_designer(browser, tmp_path, EMPTY) as (live, page, errors, saved):
        box = page.locator("#overlay").bounding_box()

        def client(px: float, py: float) -> tuple[float, float]:
            return box["x"] + px * box["width"] / 600, box["y"] + py * box["height"] / 400

        page.evaluate(f"designer.setTool('{tool}')")
        page.mouse.move(*client(*PATH[0]))
        page.mouse.down()
        for p in PATH[1:12]:
            page.mouse.move(*client(*p))
            time.sleep(0.03)
        before = live_settled(page, live)[:, :, ::-1].astype(np.uint8)

        def move() -> None:
            for p in PATH[12:24]:
                page.mouse.move(*client(*p))

        warped, image, settled = _warped_then_settled(page, live, move)
        moved = 1 - _agree(before, settled)
        assert moved > 0.01, moved  # the moves changed the picture
        agree = _agree(image, settled)
        # the page's warp shows what the session renders, far closer than the frame it warped
        assert agree > 0.97 and 1 - agree < moved / 4, (agree, moved)
        page.mouse.up()
        (op,) = wait_for(saved, f"the {tool} is saved")
        assert op["type"] == tool
        page.close()
        assert errors == []


def test_a_slider_of_the_top_op_is_warped_on_the_newest_live_frame(browser, tmp_path):
    """A slider of the top op moved over the live frames: the page's frame of the
    new value (the newest live frame, the op as it was taken off forward and the
    new one walked back) comes first and agrees with the session's frame of it."""
    comb = {"type": "comb", "point": [300, 200], "angle": 0, "alpha": 30, "lambda": 40,
            "spacing": 60}  # fmt: skip
    with live_designer(browser, tmp_path, {**EMPTY, "ops": [comb]}) as (live, page, errors, saved):
        page.click("#op-0 .name")
        slider = page.locator("#s-alpha")
        before = live_settled(page, live)[:, :, ::-1].astype(np.uint8)

        def move() -> None:  # the slider dragged to 90 (input events, not released)
            slider.evaluate(
                "(e) => { for (const v of [45, 60, 75, 90]) { e.value = v;"
                " e.dispatchEvent(new Event('input', {bubbles: true})); } }"
            )

        warped, image, settled = _warped_then_settled(page, live, move)
        moved = 1 - _agree(before, settled)
        agree = _agree(image, settled)
        assert moved > 0.01 and agree > 0.97 and 1 - agree < moved / 4, (agree, moved)
        slider.evaluate("(e) => e.dispatchEvent(new Event('change', {bubbles: true}))")
        wait_for(lambda: abs(saved()[0]["alpha"] - 90) < 0.5, "the slider's value is saved")
        page.close()
        assert errors == []


def test_with_motion_the_live_frames_are_not_warped_on_the_page(browser, tmp_path):
    """A recipe with ``motion``: the session lays the motion strokes on top of
    every op, the gesture's too, so the page cannot warp a frame to a newer
    gesture by the gesture's op; it shows the session's frames of it."""
    with live_designer(browser, tmp_path, {**EMPTY, "motion": {}}) as (live, page, errors, saved):
        before, mid, frames = _comb_held(page, live)
        assert np.abs(mid.astype(float) - before).mean() > 2  # the comb shows unsaved
        assert {f["kind"] for f in frames} == {"live"}
        page.mouse.up()
        wait_for(saved, "the comb is saved")
        page.close()
        assert errors == []
