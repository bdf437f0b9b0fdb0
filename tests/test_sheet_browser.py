"""The designer's sheet in a real headless Chromium (Playwright, SwiftShader's
WebGL2): a canvas of its displayed size in device pixels (devicePixelRatio 1
and 2), zoom and pan rendered exactly (the server's exact render of the view),
a frame drawn mid-gesture (warped on the page, or the server's quick frame)
against the exact render of the same recipe (also a handle's before its layers
come), a first frame soon and never a
black sheet, and exports at the recipe's own sizes. The sheet is compared with
the server's render of what the page says it shows (``window.marbleShown``).
Skipped, with the reason, without Playwright or Chromium."""

from __future__ import annotations

import json
import shutil
import time
import urllib.request

import cv2
import numpy as np
import pytest
from helpers import ROOT
from live_helpers import LiveProcess
from sheet_support import (
    DROPS,
    EXACT_SHARE,
    LEVELS,
    SHARE,
    comb_pressed,
    exact,
    server_render,
    sheet_page,
    shown,
    shown_when,
)

from benchmarks.realtime_probe import agreement

pytestmark = pytest.mark.tier("integration")


def under(shown: dict, fx: float, fy: float) -> tuple[float, float]:
    """The canvas point at the fraction (fx, fy) of a sheet that shows ``shown``."""
    from marblevideo.recipe.frame import fit

    x, y, vw, vh = shown["view"]
    k, dx, dy = fit((vw, vh), shown["w"], shown["h"])
    return (fx * shown["w"] - dx) / k + x, (fy * shown["h"] - dy) / k + y


@pytest.mark.parametrize("dpr", [1, 2])
def test_the_sheet_has_its_displayed_size_in_device_pixels(webgl_browser, tmp_path, dpr):
    recipe = tmp_path / "np.json"
    shutil.copy(ROOT / "samples" / "nonpareil.json", recipe)
    args = ("--ops", recipe)
    sized = sheet_page(webgl_browser, tmp_path, *args, dpr=dpr, size=(1100, 700))
    with sized as (page, app, errors):
        w, h, cw, ch = page.evaluate(
            """() => { const s = document.getElementById('sheet'), r = s.getBoundingClientRect();
                return [s.width, s.height, r.width, r.height]; }"""
        )
        assert abs(w - cw * dpr) <= 1 and abs(h - ch * dpr) <= 1, (w, h, cw, ch)
        assert w > 480 * 1.2 * dpr  # larger than the frame: never the frame's pixels scaled up
        image, what, frame = shown(page)
        assert image.shape[:2] == (h, w) and (frame["w"], frame["h"]) == (w, h)
        assert (what["w"], what["h"]) == (w, h)
        assert agreement(image, server_render(app, what), LEVELS) >= EXACT_SHARE
        # the window grows: the canvas follows, and the sheet renders at the new size
        n = page.evaluate("window.marbleFrames.at(-1).n")
        page.set_viewport_size({"width": 1300, "height": 800})
        exact(page, n)
        w2 = page.evaluate("document.getElementById('sheet').width")
        assert w2 > w and shown(page)[1]["w"] == w2
        assert errors == []


def test_zoom_and_pan_render_the_view_exactly(webgl_browser, tmp_path):
    recipe = tmp_path / "bq.json"
    shutil.copy(ROOT / "samples" / "bouquet.json", recipe)
    with sheet_page(webgl_browser, tmp_path, "--ops", recipe) as (page, app, errors):
        full = page.evaluate("window.marbleShown.view")
        for keys in (["="], ["="], ["ArrowLeft", "ArrowUp"], ["-"]):
            n = page.evaluate("window.marbleFrames.at(-1).n")
            for key in keys:
                page.keyboard.press(key)
            exact(page, n)
            image, what, _ = shown(page)
            assert agreement(image, server_render(app, what), LEVELS) >= EXACT_SHARE, keys
        assert what["view"][2] < full[2]  # zoomed in twice, out once
        # the wheel zooms about the pointer: the canvas point under it stays put
        box = page.locator("#overlay").bounding_box()
        fx, fy = 0.3, 0.6
        n = page.evaluate("window.marbleFrames.at(-1).n")
        page.mouse.move(box["x"] + box["width"] * fx, box["y"] + box["height"] * fy)
        page.mouse.wheel(0, -200)
        exact(page, n)
        image, after, _ = shown(page)
        assert agreement(image, server_render(app, after), LEVELS) >= EXACT_SHARE
        assert after["view"][2] < what["view"][2]
        pixel = what["view"][2] / what["w"]  # a device pixel, in canvas units
        assert np.allclose(under(what, fx, fy), under(after, fx, fy), atol=pixel)
        # 0 resets the view: the frame's own area again
        n = page.evaluate("window.marbleFrames.at(-1).n")
        page.keyboard.press("0")
        exact(page, n)
        assert np.allclose(shown(page)[1]["view"], full)
        assert errors == []


@pytest.mark.parametrize("query", ["", "?warp=0"])
def test_a_frame_mid_gesture_agrees_with_the_exact_render(webgl_browser, tmp_path, query):
    """A comb dragged over drops, held mid-drag: the frame drawn for the last move
    (warped on the page; with ?warp=0 the server's quick frame) agrees with the
    exact render of the recipe it shows."""
    recipe = tmp_path / "drops.json"
    recipe.write_text(json.dumps(DROPS))
    with sheet_page(webgl_browser, tmp_path, "--ops", recipe, query=query) as (page, app, errors):
        comb_pressed(page, 6)
        kind = "server-draft" if query else "warp"
        image, what, frame = shown_when(
            page,
            f"f.kind === '{kind}' && f.input !== null && designer.state.gesture !== null"
            " && window.marbleShown.doc.ops.length === designer.state.doc.ops.length + 1",
        )
        page.mouse.up()
        assert frame["kind"] == kind and frame["inputAt"] <= frame["drawnAt"]
        assert what["doc"]["ops"][-1]["type"] == "comb"
        share = agreement(image, server_render(app, what), LEVELS)
        assert share >= SHARE, share
        assert errors == []


def _alt_drag(page, k: int, step: tuple[float, float]):
    """Op ``k`` selected, its first handle pressed with Alt held and moved six
    times by ``step`` (CSS px), the button and Alt left down: (the handle's page
    point, :func:`shown_when` the first warp frame of the gesture answers a move)."""
    page.click(f"#op-{k} .name")
    box = page.locator("#overlay").bounding_box()
    px, py = page.evaluate(f"designer.toPixel(designer.handles({k})[0][1])")
    scale = box["width"] / page.evaluate("document.getElementById('overlay').width")
    x0, y0 = box["x"] + px * scale, box["y"] + py * scale
    page.keyboard.down("Alt")
    page.mouse.move(x0, y0)
    page.mouse.down()
    for i in range(1, 7):
        page.mouse.move(x0 + step[0] * i, y0 + step[1] * i)
    first = "f.kind === 'warp' && f.input !== null && designer.state.gesture !== null"
    return (x0, y0), shown_when(page, first)


def test_a_handle_dragged_mid_gesture_agrees_with_the_exact_render(webgl_browser, tmp_path):
    """The first drop's centre dragged (Alt): the page warps the server's layers of
    op 0 (nothing below it, the second drop and the wave above it as a map), and
    the frame agrees with the exact render of the recipe it shows."""
    recipe = tmp_path / "drops.json"
    recipe.write_text(json.dumps(DROPS))
    with sheet_page(webgl_browser, tmp_path, "--ops", recipe) as (page, app, errors):
        _, (image, what, _) = _alt_drag(page, 0, (6, 3))
        page.mouse.up()
        page.keyboard.up("Alt")
        assert what["doc"]["ops"][0]["center"] != DROPS["ops"][0]["center"]
        share = agreement(image, server_render(app, what), LEVELS)
        assert share >= SHARE, share
        assert errors == []


def test_a_handle_answered_before_its_layers_come(webgl_browser, tmp_path):
    """The top op's handle dragged while its layers are held back (the server's
    answer to POST /api/layers kept until the end): the page answers the moves
    from its own exact frame, the tine as it was taken off forward, and that
    frame agrees with the exact render of the recipe it shows."""
    tine = {"type": "tine", "point": [150, 110], "angle": 30, "alpha": 20, "lambda": 10}
    doc = {**DROPS, "ops": [*DROPS["ops"][:2], tine]}
    recipe = tmp_path / "tine.json"
    recipe.write_text(json.dumps(doc))
    with sheet_page(webgl_browser, tmp_path, "--ops", recipe) as (page, app, errors):
        held = []
        page.route("**/api/layers**", lambda route: held.append(route))
        (x0, y0), (image, what, frame) = _alt_drag(page, 2, (5, 4))
        interim = page.evaluate("designer.warp().interim")
        for route in held:
            route.continue_()
        # then the layers: the next moves warp them, the op as it was no longer taken off
        page.wait_for_function("designer.warp().ready && !designer.warp().interim")
        page.mouse.move(x0 + 40, y0 + 20)
        page.mouse.move(x0 + 44, y0 + 18)
        later = shown_when(page, f"f.kind === 'warp' && f.n > {frame['n']} + 1")
        page.mouse.up()
        page.keyboard.up("Alt")
        assert held and interim, (len(held), interim)
        assert what["doc"]["ops"][2]["point"] != doc["ops"][2]["point"]
        for pixels, shows in ((image, what), later[:2]):
            share = agreement(pixels, server_render(app, shows), LEVELS)
            assert share >= SHARE, share
        assert errors == []


def test_a_first_frame_soon_and_never_a_black_sheet(webgl_browser, tmp_path):
    recipe = tmp_path / "np.json"
    shutil.copy(ROOT / "samples" / "nonpareil.json", recipe)
    app = LiveProcess(
        "--ops", recipe, "--no-browser", "--port", "0", "--duration", "120",
        cwd=tmp_path, command="design",
    )  # fmt: skip
    try:
        page = webgl_browser.new_page(viewport={"width": 760, "height": 520})
        start = time.monotonic()
        page.goto(app.url, wait_until="commit")
        page.wait_for_selector("canvas#sheet")
        darkest = []
        while time.monotonic() - start < 60:
            got = page.evaluate(
                """() => { const s = document.getElementById('sheet');
                    const d = s.getContext('2d').getImageData(0, 0, s.width, s.height).data;
                    let m = 0;
                    for (let i = 0; i < d.length; i += 388) {  // transparent: the CSS ground
                        m = Math.max(m, d[i + 3] ? Math.max(d[i], d[i + 1], d[i + 2]) : 255);
                    }
                    const n = (window.marbleFrames || []).length;
                    return [m, n, getComputedStyle(s).backgroundColor]; }"""
            )
            darkest.append(got[0])
            assert got[2] != "rgb(0, 0, 0)"
            if got[1] > 0:
                break
            time.sleep(0.05)
        first = time.monotonic() - start
        assert got[1] > 0 and first < 30, first  # the first frame (a quick one) comes
        assert min(darkest) > 0  # the ground before it, never black
        exact(page)
        page.close()
    finally:
        assert app.stop() == 0


def test_exports_keep_the_recipes_sizes(webgl_browser, tmp_path):
    """The export links of a zoomed sheet shown at devicePixelRatio 2 give the
    recipe's frame (480x320), not the sheet's size or view."""
    recipe = tmp_path / "np.json"
    shutil.copy(ROOT / "samples" / "nonpareil.json", recipe)
    with sheet_page(webgl_browser, tmp_path, "--ops", recipe, dpr=2) as (page, app, errors):
        n = page.evaluate("window.marbleFrames.at(-1).n")
        page.keyboard.press("=")
        exact(page, n)
        assert page.evaluate("document.getElementById('sheet').width") > 480
        png = urllib.request.urlopen(app.url + page.get_attribute("#export-png", "href")[1:])
        image = cv2.imdecode(np.frombuffer(png.read(), np.uint8), cv2.IMREAD_COLOR)
        assert image.shape[:2] == (320, 480)
        svg = urllib.request.urlopen(app.url + page.get_attribute("#export-svg", "href")[1:])
        head = svg.read(600).decode()
        assert 'width="480"' in head and 'height="320"' in head, head
        assert errors == []
