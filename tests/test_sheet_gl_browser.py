"""The warp's WebGL canvas shown as the sheet during a gesture (sheetgl.js), in a
real headless Chromium (SwiftShader's WebGL2): mid-gesture, what the screen shows
(a screenshot of the sheet's box, the overlay hidden) is what the page reports
it shows (``designer.sheetPixels``) and agrees with the server's exact render of
what ``window.marbleShown`` says; after letting go the 2D sheet takes the exact
frame and the WebGL canvas is hidden. With ``?glsheet=0`` the warped frames are
read back into the 2D sheet, which the screen shows throughout."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from sheet_support import (
    DROPS,
    LEVELS,
    SHARE,
    SHOWN_PNG,
    comb_pressed,
    decode_png,
    exact,
    server_render,
    sheet_page,
)

from benchmarks.realtime_probe import agreement

pytestmark = pytest.mark.tier("integration")

#: The screen against the pixels the page reports: the same frame (the
#: compositor's copy may round an edge or two).
ON_SCREEN = 0.999


def on_screen(page) -> np.ndarray:
    """The sheet's box as the screen shows it (RGB, the sheet's device size), the overlay hidden."""
    page.evaluate("document.getElementById('overlay').style.visibility = 'hidden'")
    box = page.locator("#sheet").bounding_box()
    png = page.screenshot(clip=box, animations="disabled")
    page.evaluate("document.getElementById('overlay').style.visibility = ''")
    image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)[:, :, ::-1]
    w, h = page.evaluate(
        "[document.getElementById('sheet').width, document.getElementById('sheet').height]"
    )
    return (
        image
        if image.shape[:2] == (h, w)
        else cv2.resize(image, (w, h), interpolation=cv2.INTER_AREA)
    )


#: The newest move's warped frame, once drawn: its number and whether the
#: WebGL canvas shows the sheet then.
WARPED = """(n0) => new Promise((resolve) => {
    const look = () => {
        const f = window.marbleFrames.at(-1);
        if (f.n <= n0) { requestAnimationFrame(look); return; }
        const warped = f.kind === 'warp' && designer.state.gesture !== null
            && window.marbleShown.doc.ops.length === designer.state.doc.ops.length + 1;
        resolve([warped ? f.n : -1, designer.glShown()]);
    };
    look();
})"""


def reported(page) -> np.ndarray:
    """The pixels the page reports its sheet shows (RGB)."""
    return decode_png(page.evaluate(SHOWN_PNG))


@pytest.mark.parametrize("query", ["", "?glsheet=0"])
def test_the_screen_shows_what_the_page_reports_mid_gesture(webgl_browser, tmp_path, query):
    recipe = tmp_path / "drops.json"
    recipe.write_text(json.dumps(DROPS))
    with sheet_page(webgl_browser, tmp_path, "--ops", recipe, query=query) as (page, app, errors):
        x0, y0 = comb_pressed(page, 8)
        for i in range(9, 15):  # (a frame may come while the screen is taken: then again)
            n0 = page.evaluate("window.marbleFrames.at(-1).n")
            page.mouse.move(x0 + 12 * i, y0 + 5 * i)
            n, gl_mid = page.evaluate(WARPED, n0)
            screen, now = on_screen(page), reported(page)
            what = page.evaluate("window.marbleShown")
            if page.evaluate("window.marbleFrames.at(-1).n") == n:
                break
        assert page.evaluate("window.marbleFrames.at(-1)")["kind"] == "warp"
        page.mouse.up()
        exact(page, n)
        gl_after = page.evaluate("designer.glShown()")
        settled, settled_now = on_screen(page), reported(page)
        assert gl_mid is (query == ""), gl_mid
        # (the comb moves a few % of the pixels: the screen must be the frame itself)
        assert agreement(screen, now, LEVELS) >= ON_SCREEN, agreement(screen, now, LEVELS)
        assert agreement(now, server_render(app, what), LEVELS) >= SHARE
        assert gl_after is False
        assert agreement(settled, settled_now, LEVELS) >= ON_SCREEN
        assert errors == []
