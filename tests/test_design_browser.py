"""The designer's page driven by the mouse in a real headless Chromium
(Playwright), over samples/coffee.jpg with a 400x300 canvas, so the canvas is
scaled (4/3) and centred in the 600x400 frame: a click must land on the canvas
point the contract's geometry gives. Skipped, with the reason, when Playwright
or Chromium is missing."""

from __future__ import annotations

import json
import math
import time

import cv2
import numpy as np
import pytest
from helpers import ROOT
from live_helpers import (
    INK,
    REFUSED,
    LiveProcess,
    designer_page,
    drag,
    frames,
    pixel,
    settled,
    wait_for,
)

pytestmark = pytest.mark.tier("integration")

COFFEE = ROOT / "samples" / "coffee.jpg"


def test_draw_undo_refuse_and_follow_the_file(coffee_designer):
    d = coffee_designer
    page, errors, saved, client, recipe = d.page, d.errors, d.saved, d.client, d.recipe
    s, dx, dy = d.s, d.dx, d.dy

    # the drop tool is active at load: a click drops ink where it was clicked
    assert "on" in page.get_attribute("#tool-drop", "class")
    n = frames(page)
    page.mouse.click(*client(180, 160))
    ops = wait_for(saved, "the drop is saved")
    assert [op["type"] for op in ops] == ["drop"]
    cx, cy = ops[0]["center"]
    assert (abs(cx - (180 - dx) / s) <= 0.11, abs(cy - (160 - dy) / s) <= 0.11) == (True, True)
    assert (round(cx), round(cy)) == (110, 120)
    settled(page, n)
    assert pixel(page, 180, 160) == INK  # the exact render shows it there
    assert pixel(page, 560, 30) != INK

    # a drag with the comb tool: a comb along the drag's direction, of a modest
    # strength (it moves the whole sheet by alpha at its tines, so not the drag's
    # length: a tenth of it, at most the spacing), shown while dragging
    page.click("#tool-comb")
    n = frames(page)
    a, b = (120, 200), (360, 320)
    label = drag(page, client, a, b)
    ops = wait_for(lambda: len(saved()) == 2 and saved(), "the comb is saved")
    comb = ops[1]
    assert comb["type"] == "comb"
    assert abs(comb["angle"] - math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))) < 0.3
    assert abs(comb["point"][0] - (a[0] - dx) / s) < 0.2
    assert comb["spacing"] == round(300 / 16, 1)
    assert comb["alpha"] == min(round(math.dist(a, b) / s / 10, 1), comb["spacing"]) > 0
    assert label == f"alpha {comb['alpha']:g}"
    assert page.get_attribute("#overlay", "data-label") == ""  # let go: gone
    settled(page, n)
    assert page.text_content("#oplist") == "0 drop" + "hidesolo↑↓✕" + "1 comb" + "hidesolo↑↓✕"

    # undo removes it, redo brings it back, undo again
    page.click("#undo")
    wait_for(lambda: [op["type"] for op in saved()] == ["drop"], "undone")
    page.click("#redo")
    wait_for(lambda: saved() == ops, "redone")
    # undo by Ctrl-Z, and hide at once (hide is saved as "hidden": true): an edit
    # made while a save is on its way applies to what that save left
    n = frames(page)
    page.keyboard.press("Control+z")
    page.click("#op-0 button[data-act=hide]")
    hidden = [{**ops[0], "hidden": True}]
    wait_for(lambda: saved() == hidden, "undone, then hidden")
    settled(page, n, ops=hidden)
    assert pixel(page, 180, 160) != INK
    assert page.text_content("#op-0 button[data-act=hide]") == "show"
    n = frames(page)
    page.click("#op-0 button[data-act=hide]")
    wait_for(lambda: saved() == ops[:1], "the show is saved")
    settled(page, n, ops=ops[:1])
    assert pixel(page, 180, 160) == INK

    # an invalid edit is refused with its JSON path; the file is kept
    page.click("#op-0 .name")
    assert errors == []
    before = recipe.read_bytes()
    page.fill("#p-radius", "-2")
    page.press("#p-radius", "Enter")
    page.wait_for_selector("#error", state="visible")
    assert "coffee.json: ops[0].radius: must be > 0, got -2" in page.text_content("#error")
    assert recipe.read_bytes() == before
    assert page.input_value("#p-radius") == str(ops[0]["radius"])
    assert errors == [REFUSED]  # Chromium logs the refused PUT; nothing else
    errors.clear()
    # a valid one is saved
    page.fill("#p-radius", "30")
    page.press("#p-radius", "Enter")
    wait_for(lambda: saved()[0]["radius"] == 30, "the radius is saved")
    page.wait_for_selector("#error", state="hidden")
    # its slider: moved, the sheet shows a draft; let go, the value is saved
    n = frames(page)
    page.locator("#s-radius").evaluate(
        "el => { el.value = 50; el.dispatchEvent(new Event('input')); }"
    )
    page.wait_for_function(
        f"document.getElementById('sheet').dataset.frames > {n} "
        "&& document.getElementById('sheet').dataset.draft === '1'"
    )
    assert saved()[0]["radius"] == 30
    page.locator("#s-radius").evaluate("el => el.dispatchEvent(new Event('change'))")
    wait_for(lambda: abs(saved()[0]["radius"] - 50) < 0.2, "the slider's radius is saved")

    # hot reload: another program saves FILE; the page follows
    doc = json.loads(recipe.read_text())
    doc["ops"][0]["radius"] = 12.5
    recipe.write_text(json.dumps(doc))
    page.wait_for_function("document.getElementById('p-radius').value === '12.5'")

    # the timeline: "key" sets a keyframe at the time shown; play moves the clock
    page.locator("#time").evaluate(
        "el => { el.value = el.max; el.dispatchEvent(new Event('input')); }"
    )
    page.fill("#p-radius", "40")
    page.click("#key-radius")
    wait_for(lambda: isinstance(saved()[0]["radius"], dict), "the key is saved")
    assert saved()[0]["radius"] == {"keys": [{"t": 0, "v": 12.5}, {"t": 1, "v": 40}]}
    page.click("#play")
    page.wait_for_function("document.getElementById('clock').textContent !== 't = 1.00 s'")
    page.click("#play")
    assert page.text_content("#play") == "Play"
    time.sleep(0.5)  # the key stays (the field typed in is not saved again as it goes)
    assert saved()[0]["radius"] == {"keys": [{"t": 0, "v": 12.5}, {"t": 1, "v": 40}]}
    assert errors == []


def test_a_nonpareil_a_bouquet_and_a_swirl_over_a_photo_by_mouse_then_rendered(
    browser, tmp_path, cli
):
    """A user's first session: drops scattered and raked down and back up (a nonpareil),
    waved and raked across (a bouquet), then a vortex (a swirl), all by mouse over
    samples/coffee.jpg; the saved recipe renders with the main command."""
    recipe = tmp_path / "mine.json"
    app = LiveProcess(
        COFFEE, "--ops", recipe, "--no-browser", "--port", "0", "--duration", "120",
        cwd=tmp_path, command="design",
    )  # fmt: skip
    try:
        page = browser.new_page(viewport={"width": 1300, "height": 900})
        page.goto(app.url)
        page.wait_for_selector("body[data-ready='1']")
        box = page.locator("#overlay").bounding_box()

        def client(px: float, py: float) -> tuple[float, float]:
            return box["x"] + px * box["width"] / 600, box["y"] + py * box["height"] / 400

        for tool, a, b in (
            ("scatter-drops", (300, 200), (560, 380)),
            ("rake", (300, 40), (300, 200)),
            ("rake", (310, 360), (310, 200)),
            ("wave", (300, 200), (300, 260)),
            ("rake", (100, 200), (250, 200)),
            ("vortex", (300, 200), (380, 200)),
        ):
            page.click(f"#tool-{tool}")
            count = len(json.loads(recipe.read_text())["ops"])
            drag(page, client, a, b)
            wait_for(lambda n=count: len(json.loads(recipe.read_text())["ops"]) > n, tool)
        ops = json.loads(recipe.read_text())["ops"]
        types = ["scatter-drops", "rake", "rake", "wave", "rake", "vortex"]
        assert [op["type"] for op in ops] == types
        assert (ops[1]["angle"], ops[2]["angle"], ops[4]["angle"]) == (90, -90, 0)
        page.close()
    finally:
        assert app.stop() == 0
    proc = cli(COFFEE, "--ops", recipe, "-o", tmp_path / "mine.png")
    assert proc.returncode == 0, proc.stderr
    out = cv2.imread(str(tmp_path / "mine.png"))
    photo = cv2.imread(str(COFFEE))
    assert out.shape == photo.shape and np.abs(out.astype(int) - photo).mean() > 10


def test_the_pages_keyed_values_are_the_renderers(browser, tmp_path):
    """Where a slider on a keyed number starts: the page's copy of the track's
    evaluation (eases included) against marblevideo.recipe.keyframes, on every
    named ease, a custom cubic-bezier (a flat-then-steep one that needs the
    bisection), hold, before the first key, on keys and after the last."""
    from marblevideo.recipe import parse_recipe

    tracks = [
        {"keys": [{"t": 0.5, "v": 10, "ease": ease}, {"t": 2.5, "v": -30}, {"t": 3, "v": 5}]}
        for ease in ("linear", "hold", "ease-in", "ease-out", "ease-in-out", [0, 0.9, 0, 1],
                     [0.7, -0.4, 0.2, 1.6])
    ]  # fmt: skip
    times = [0, 0.5, 0.6, 1.0, 1.37, 2.0, 2.49, 2.5, 2.8, 3, 4]
    recipe = tmp_path / "k.json"
    with designer_page(browser, tmp_path, "--ops", recipe, "--canvas", "200x100") as (page, errors):
        ours = page.evaluate(
            "([tracks, times]) => tracks.map((v) => times.map((tt) => designer.valueNow(v, tt)))",
            [tracks, times],
        )
    for track, row in zip(tracks, ours, strict=True):
        op = {"type": "tine", "point": [0, 0], "angle": 0, "alpha": track, "lambda": 5}
        alpha = parse_recipe({"canvas": [200, 100], "ops": [op]}).ops[0].params["alpha"]
        expected = [alpha.at(tt) for tt in times]
        assert np.allclose(row, expected, rtol=0, atol=1e-9), (track["keys"][0]["ease"], row)
    assert errors == []


def test_a_click_as_the_page_appears_reaches_the_file(browser, tmp_path):
    """Pointer input before the page has the recipe (here held back by keeping its
    /api/info request waiting) is replayed once it has: the drop lands where the
    sheet was clicked, as a fraction of the sheet (its centre: the canvas's)."""
    recipe = tmp_path / "early.json"
    app = LiveProcess(
        "--ops", recipe, "--canvas", "400x300", "--no-browser", "--port", "0",
        "--duration", "60", cwd=tmp_path, command="design",
    )  # fmt: skip
    try:
        page = browser.new_page(viewport={"width": 1300, "height": 900})
        held = []
        # the first /api/info (the page's start) is held; later ones (its polls) go on
        page.route("**/api/info", lambda route: route.continue_() if held else held.append(route))
        page.goto(app.url, wait_until="commit")
        page.wait_for_selector("canvas#sheet")
        while not held:  # the page's script runs: it asked for /api/info
            page.wait_for_timeout(20)
        assert page.get_attribute("body", "data-ready") is None
        assert page.eval_on_selector("#overlay", "el => getComputedStyle(el).cursor") == "progress"
        box = page.locator("#overlay").bounding_box()
        page.mouse.click(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        assert json.loads(recipe.read_text())["ops"] == []
        held[0].continue_()
        page.wait_for_selector("body[data-ready='1']")
        ops = wait_for(lambda: json.loads(recipe.read_text())["ops"], "the early click's drop")
        assert [op["type"] for op in ops] == ["drop"]
        assert max(abs(ops[0]["center"][0] - 200), abs(ops[0]["center"][1] - 150)) <= 0.5
        assert page.eval_on_selector("#overlay", "el => getComputedStyle(el).cursor") == "crosshair"
        page.close()
    finally:
        assert app.stop() == 0
