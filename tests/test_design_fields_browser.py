"""The designer's page and its fields, in a real headless Chromium (Playwright):
the keyboard's shortcuts leave a field that has the focus alone (a text, number
or colour field, a menu, a contenteditable), a keyed parameter is shown as its
keys, and the live timeline says where the session's clock is. Skipped, with
the reason, when Playwright or Chromium is missing."""

from __future__ import annotations

import json

import pytest
from live_helpers import RECIPE, designer_page, live_designer, wait_for

pytestmark = pytest.mark.tier("integration")

DROP = {"type": "drop", "center": [200, 150], "radius": 30, "color": "#1d3557"}


def _recipe(folder, *ops) -> object:
    path = folder / "fields.json"
    path.write_text(json.dumps({"marblevideo": 1, "canvas": [400, 300], "ops": list(ops)}))
    return path


def _page_state(page) -> dict:
    return page.evaluate(
        """() => { const s = designer.state;
            return {tool: s.tool, moving: s.moving, view: s.view, selected: s.selected,
                    ops: s.doc.ops.length, undo: s.undo.length}; }"""
    )


def test_shortcuts_leave_a_focused_field_alone(browser, tmp_path):
    recipe = _recipe(tmp_path, DROP)
    with designer_page(browser, tmp_path, "--ops", recipe) as (page, errors):
        page.click("#op-0 .name")
        before = _page_state(page)
        assert before["selected"] == 0 and before["tool"] == "drop"
        # keys typed into a number field are the field's: no tool, no delete, no zoom
        page.click("#p-radius")
        for key in ("Delete", "Backspace", "c", "m", "+", "0", "ArrowLeft", "Escape", " "):
            page.keyboard.press(key)
        page.keyboard.type("4k5")
        assert _page_state(page) == before
        page.fill("#p-radius", "30")  # left as it was: the field saves what it holds as it blurs
        # ... and into a contenteditable one (Space is typed, not taken for a pan)
        page.evaluate(
            """() => { const el = document.createElement('div');
                el.id = 'notes'; el.contentEditable = 'true';
                document.querySelector('aside').append(el); }"""
        )
        page.click("#notes")
        page.keyboard.type("a b c")
        page.keyboard.press("Delete")
        assert page.text_content("#notes") == "a b c"
        assert _page_state(page) == before

        # Space held with the focus still in the ground colour field, then a drag
        # on the sheet: that pans (the press takes the focus); no drop is added
        page.click("#ground")
        page.keyboard.press("Escape")  # the colour chooser, if one opened, closed
        page.focus("#ground")
        box = page.locator("#overlay").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.keyboard.down(" ")
        page.mouse.move(x, y)
        page.mouse.down()
        for k in range(1, 6):
            page.mouse.move(x + 12 * k, y + 6 * k)
        page.mouse.up()
        page.keyboard.up(" ")
        after = _page_state(page)
        assert after["view"] is not None, "Space + drag did not pan"
        assert after["ops"] == 1 and json.loads(recipe.read_text())["ops"] == [DROP]
        assert page.evaluate("document.activeElement.id") != "ground"
        # with the focus on the page again, the keys are shortcuts
        page.keyboard.press("0")
        wait_for(lambda: _page_state(page)["view"] is None, "0 resets the view")
        page.keyboard.press("c")
        wait_for(lambda: _page_state(page)["tool"] == "comb", "C picks the comb")
    assert errors == []


def test_the_live_timeline_says_the_clock_is_past_the_recipes_end(browser, tmp_path):
    """``live --preview`` with loop off: the session's clock runs on past the
    recipe's end (1 s); the clock says so, with the session's time, and the time
    slider rests at the end."""
    with live_designer(browser, tmp_path, RECIPE) as (live, page, errors, _saved):
        assert not page.is_checked("#loop")
        live.wait_stats(lambda s: s["t"] > 2.0 and s["loop"] is None)
        page.wait_for_function(
            """() => { const m = /^t = ([0-9.]+) s, past the recipe's end \\(1\\.00 s\\)$/
                    .exec(document.getElementById('clock').textContent);
                return m && Number(m[1]) > 2; }"""
        )
        shown = float(page.text_content("#clock").split()[2])
        assert abs(shown - live.get("/stats")["t"]) < 2.0
        assert float(page.input_value("#time")) == 1
        # within the recipe again (a seek), the clock is the plain time shown
        page.locator("#time").evaluate(
            "el => { el.value = 0.5; el.dispatchEvent(new Event('input', {bubbles: true})); }"
        )
        page.click("#play")  # paused there
        live.wait_stats(lambda s: s["paused"])
        page.wait_for_function(
            "/^t = 0\\.[5-9][0-9] s$/.test(document.getElementById('clock').textContent)"
        )
    assert errors == []
