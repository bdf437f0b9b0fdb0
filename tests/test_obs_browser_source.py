"""docs/obs.md's Browser Source: the preview's MJPEG URL, opened in Chromium
at the sizes OBS asks (its default 800x600, and the session's 1280x720 that the
docs tell to set), shows the marbled frames filling the view, and they move."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import ROOT
from live_helpers import LiveProcess

pytestmark = pytest.mark.tier("integration")

CSS = (
    "body { margin: 0; overflow: hidden; } "
    "img { width: 100vw; height: 100vh; object-fit: contain; }"
)


def test_the_docs_css_is_the_one_tried():
    assert CSS in " ".join((ROOT / "docs" / "obs.md").read_text().split())


@pytest.mark.parametrize("size", [(800, 600), (1280, 720)])
def test_the_mjpeg_url_fills_a_browser_source(browser, tmp_path, size):
    (tmp_path / "still.json").write_text(
        json.dumps(
            {
                "marblevideo": 1,
                "ops": [{"type": "vortex", "center": [320, 180], "alpha": 200, "lambda": 80}],
            }
        )
    )
    args = ["test", "--ops", "still.json", "--size", "640x360", "--fps", "10", "--preview"]
    live = LiveProcess(*args, "--port", "0", "--duration", "60", cwd=tmp_path)
    try:
        live.wait_stats(lambda s: s["jpeg_seq"] > 2, timeout=60)
        page = browser.new_page(viewport={"width": size[0], "height": size[1]})
        page.goto(live.url.rstrip("/") + "/stream.mjpg", wait_until="commit")  # never loads
        page.add_style_tag(content=CSS)
        page.wait_for_function("document.images.length && document.images[0].naturalWidth > 0")
        natural = page.evaluate(
            "[document.images[0].naturalWidth, document.images[0].naturalHeight]"
        )
        box = page.evaluate(
            "(r => [r.width, r.height])(document.images[0].getBoundingClientRect())"
        )
        first = np.frombuffer(page.screenshot(type="png"), np.uint8)
        page.wait_for_timeout(1500)
        second = np.frombuffer(page.screenshot(type="png"), np.uint8)
        page.close()
    finally:
        assert live.stop() == 0, live.stderr()
    assert natural == [640, 360]
    assert box == [size[0], size[1]]
    assert not np.array_equal(first, second), "the frames do not move"
