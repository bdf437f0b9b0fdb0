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


#: Tracks and how a field shows them (a key's ease, in brackets, leaves it).
SHOWN_KEYS = [
    ({"keys": [{"t": 0, "v": 10, "ease": "ease-in-out"}, {"t": 1.5, "v": 18}]},
     "0 s: 10 (ease-in-out) → 1.5 s: 18"),
    ({"keys": [{"t": 0.25, "v": -3.5, "ease": [0, 0.9, 0, 1]},
               {"t": 2, "v": 1e-7, "ease": "hold"}]},
     "0.25 s: -3.5 (0, 0.9, 0, 1) → 2 s: 1e-7 (hold)"),
    ({"keys": [{"t": 0, "v": [10, 20.5]}, {"t": 1, "v": [30, 40]}]},
     "0 s: [10, 20.5] → 1 s: [30, 40]"),
    ({"keys": [{"t": 0, "v": "#1d3557", "ease": "linear"}, {"t": 3, "v": "white"}]},
     "0 s: #1d3557 (linear) → 3 s: white"),
]  # fmt: skip


def test_a_keyed_field_shows_its_keys_as_a_list(browser, tmp_path):
    track, text = SHOWN_KEYS[0]
    recipe = _recipe(tmp_path, {**DROP, "radius": track})
    with designer_page(browser, tmp_path, "--ops", recipe) as (page, errors):
        page.click("#op-0 .name")
        assert page.input_value("#p-radius") == text
        # each track's list reads back as the track, and the lists as typed by hand
        back = page.evaluate(
            """async (cases) => { const m = await import('/web/keys.js');
                return cases.map(([track, text]) => [m.keysText(track), m.parseField(text)]); }""",
            SHOWN_KEYS,
        )
        assert back == [[text, track] for track, text in SHOWN_KEYS]
        typed = page.evaluate(
            """async () => { const m = await import('/web/keys.js');
                return [m.parseField('0s:1->2 s : 3(ease-in)'), m.parseField('12'),
                        m.parseField('#ff0000'), m.parseField('  ')]; }"""
        )
        assert typed == [{"keys": [{"t": 0, "v": 1}, {"t": 2, "v": 3, "ease": "ease-in"}]}, 12,
                         "#ff0000", None]  # fmt: skip
        # edited as a list, it saves the keys
        page.fill("#p-radius", "0 s: 10 → 2 s: 25 (hold) → 3 s: 5")
        page.press("#p-radius", "Enter")
        expected = {
            "keys": [{"t": 0, "v": 10}, {"t": 2, "v": 25, "ease": "hold"}, {"t": 3, "v": 5}]
        }
        wait_for(lambda: json.loads(recipe.read_text())["ops"][0]["radius"] == expected, "saved")
        page.wait_for_function(
            "document.getElementById('p-radius').value === '0 s: 10 → 2 s: 25 (hold) → 3 s: 5'"
        )
        # a list it cannot read: one line, the file kept
        before = recipe.read_bytes()
        page.fill("#p-radius", "0 s: 10 → soon: 4")
        page.press("#p-radius", "Enter")
        page.wait_for_selector("#error", state="visible")
        assert page.text_content("#error").startswith("ops[0].radius: key 2 'soon: 4': expected")
        assert recipe.read_bytes() == before
    assert errors == []
