"""The live preview page driven in a real headless Chromium (Playwright).

The source is a still photo looped (``samples/coffee.jpg --loop``), so with the
animation clock paused every frame is the same and any change comes from the
controls. Skipped, with the reason, when Playwright or Chromium is missing
(``pip install playwright``; ``apt-get install chromium``).
"""

from __future__ import annotations

import copy
import json
import time

import cv2
import numpy as np

from tests.live_helpers import RECIPE, ROOT, LiveProcess


def _shot(page) -> np.ndarray:
    png = page.locator("#view").screenshot()
    return cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR).astype(np.int16)


def _diff(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).mean())


def _settled(page, live, wait: float = 0.6) -> np.ndarray:
    """A screenshot taken once frames rendered after now have reached the page."""
    seq = live.get("/stats")["jpeg_seq"]
    live.wait_stats(lambda s: s["jpeg_seq"] >= seq + 3)
    time.sleep(wait)
    return _shot(page)


def test_preview_page_streams_controls_and_reloads(browser, tmp_path):
    recipe = tmp_path / "live.json"
    recipe.write_text(json.dumps(RECIPE))
    live = LiveProcess(
        ROOT / "samples" / "coffee.jpg", "--loop", "--ops", recipe, "--preview", "--port", "0",
        "--duration", "60", cwd=tmp_path,
    )  # fmt: skip
    try:
        page = browser.new_page()
        page.goto(live.url)
        # frames arrive and the counters move
        page.wait_for_function("Number(document.getElementById('frames').textContent) > 5")
        first = int(page.text_content("#frames"))
        page.wait_for_function(f"Number(document.getElementById('frames').textContent) > {first}")
        page.wait_for_selector("#param-1-alpha")
        assert page.locator("text=amplitude: animated").count() == 1

        # paused clock + still source: the picture holds still ...
        page.click("#pause")
        page.wait_for_function("document.getElementById('pause').textContent === 'Resume'")
        a = _settled(page, live)
        b = _settled(page, live)
        assert _diff(a, b) < 1.0
        # ... until a slider moves
        page.locator("#param-1-alpha").evaluate(
            "el => { el.value = el.min; el.dispatchEvent(new Event('input', {bubbles: true})); }"
        )
        live.wait_stats(lambda s: s["overrides"] and s["overrides"][0]["value"] < 0)
        c = _settled(page, live)
        assert _diff(a, c) > 5 * max(_diff(a, b), 0.2)
        # bypass shows the source, mirror flips it; both undo
        for box in ("#bypass", "#mirror"):
            page.check(box)
            live.wait_stats(lambda s, key=box[1:]: s[key])
            assert _diff(c, _settled(page, live)) > 5 * max(_diff(a, b), 0.2)
            page.uncheck(box)
            live.wait_stats(lambda s, key=box[1:]: not s[key])

        # a valid save is picked up: new version, new sliders (overrides reset)
        good = copy.deepcopy(RECIPE)
        good["ops"][1]["lambda"] = 25
        recipe.write_text(json.dumps(good))
        page.wait_for_function("document.getElementById('version').textContent === '2'")
        page.wait_for_function(
            "document.getElementById('param-1-lambda') && "
            "Number(document.getElementById('param-1-lambda').value) === 25"
        )
        d = _settled(page, live)
        assert _diff(c, d) > 5 * max(_diff(a, b), 0.2)

        # an invalid save shows its error; the previous recipe keeps running
        bad = copy.deepcopy(good)
        bad["ops"][1]["lambda"] = -2
        recipe.write_text(json.dumps(bad))
        page.wait_for_selector("#recipe-error", state="visible")
        assert "ops[1].lambda" in page.text_content("#recipe-error")
        frames = int(page.text_content("#frames"))
        page.wait_for_function(
            f"Number(document.getElementById('frames').textContent) > {frames + 5}"
        )
        assert page.text_content("#version") == "2"
        e = _settled(page, live)
        assert _diff(d, e) < 1.0
        page.close()
    finally:
        rc = live.stop()
    assert rc == 0
    err = live.stderr()
    line = [x for x in err.splitlines() if "ops[1].lambda" in x]
    assert len(line) == 1 and "keeping the previous recipe" in line[0], err
