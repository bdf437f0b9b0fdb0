"""The page's ES modules (marblevideo/design/web) unit-tested in a real headless
Chromium, loaded from the real designer's server (``/web/NAME``) and checked
against Python on vectors Python makes: the easing (ease.js against
marblevideo.recipe.keyframes.ease), the slider ranges (range.js on /api/ops's
laws against marblevideo.ops.slider_range), and the tool table and the ops its
tools make (tools.js on /api/ops against marblevideo.ops.gestures); the store's
subscriptions, the actions table's hints and the tools' keys, a gesture's
states (idle, pointing, dragging) with the keys that undo it, and a path drawn
in time (stylus.js: a point per device pixel, times non-decreasing, halved past
MAX_POINTS). One server
and one page for the module; skipped, with the reason, without Playwright or
Chromium."""

from __future__ import annotations

import math

import numpy as np
import pytest
from live_helpers import designer_page

from marblevideo.design.describe import describe_ops
from marblevideo.ops import LAYOUTS, REGISTRY, slider_range
from marblevideo.ops.gestures import evaluate, gesture_env, make_op
from marblevideo.recipe.keyframes import BEZIERS, ease

pytestmark = pytest.mark.tier("integration")

DEFINITIONS = {**REGISTRY, **LAYOUTS}
CANVAS = (200, 100)  # the server's blank sheet: its frame is the canvas (scale 1)
INKS = ["#1d3557", "#b23a48", "#e9c46a"]
PATH = [[20.0, 60.0], [60.0, 30.5], [100.0, 70.0], [150.0, 40.0]]
#: (a, b) gestures: a click, then drags every way.
GESTURE_ENDS = [((100, 50), (100, 50)), ((30, 20), (170, 90)), ((150, 80), (40, 10.5))]


@pytest.fixture(scope="module")
def page(browser, tmp_path_factory):
    """The designer's page on a blank 200x100 sheet, once it is ready."""
    folder = tmp_path_factory.mktemp("modules")
    with designer_page(browser, folder, "--ops", folder / "m.json", "--canvas", "200x100") as (
        page,
        errors,
    ):
        yield page
        assert errors == []


def run(page, module: str, body: str, arg):
    """``body`` (a function of the module ``m`` and ``arg``) run in the page."""
    return page.evaluate(
        f"async (arg) => {{ const m = await import('/web/{module}'); return ({body})(m, arg); }}",
        arg,
    )


def test_easing_is_the_renderers(page):
    rng = np.random.default_rng(31)
    beziers = [[0, 0.9, 0, 1], [0.7, -0.4, 0.2, 1.6], [1, 0, 0, 1], [0.01, 1, 0.99, 0]]
    beziers += rng.uniform([0, -1, 0, -1], [1, 2, 1, 2], (12, 4)).round(4).tolist()
    specs = ["linear", "hold", *BEZIERS, *beziers]
    us = [-0.1, 0, 1e-9, 0.001, 0.25, 0.5, 0.5 + 1e-12, 0.73, 0.999, 1, 1.2]
    us += rng.uniform(0, 1, 20).tolist()
    expected = [[float(ease(s, u)) for u in us] for s in specs]
    body = "(m, [specs, us]) => specs.map((s) => us.map((u) => m.eased(s, u)))"
    ours = run(page, "ease.js", body, [specs, us])
    for spec, row, want in zip(specs, ours, expected, strict=True):
        assert np.allclose(row, want, rtol=0, atol=1e-12), spec


def test_slider_ranges_are_pythons(page):
    rng = np.random.default_rng(5)
    values = [0, 1, -1, 179.5, -361.2, 0.05, *rng.uniform(-5000, 5000, 6).round(3).tolist()]
    sizes = [80, 200, 1920, 333.3]
    described = describe_ops()
    cases, expected = [], []
    for type_, d in described.items():
        for p in d["params"]:
            if p["slider"] is None:
                continue
            param = next(q for q in DEFINITIONS[type_].params if q.name == p["name"])
            for v in values:
                for size in sizes:
                    cases.append([p, v, size])
                    expected.append(list(slider_range(param, v, size)))
    ours = run(page, "range.js", "(m, cases) => cases.map(([p, v, s]) => m.sliderRange(p, v, s))",
               cases)  # fmt: skip
    assert len(cases) > 500
    assert ours == expected  # exactly: the page's slider bounds are Python's


def _close(a, b) -> bool:
    if isinstance(a, list | tuple):
        return len(a) == len(b) and all(_close(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_close(a[k], b[k]) for k in a)
    if isinstance(a, str):
        return a == b
    return math.isclose(a, b, rel_tol=0, abs_tol=1e-9)


TOOL_OPS = """(m, [types, ends, side, more]) => {
    const table = m.buildTools(types);
    return [table.map((t) => t.name), table.map((tool) => ends.map(([a, b]) => {
        const env = m.gestureEnv(a, b, side, 1, more);
        const setting = (s) => [s.name, m.evaluate(s.default, env)];
        env.setting = Object.fromEntries(tool.settings.map(setting));
        return m.makeOp(tool, env);
    }))];
}"""


def test_the_tool_table_and_its_ops_are_pythons(page):
    types = page.evaluate("async () => (await fetch('/api/ops')).json()")
    assert types == describe_ops()
    more = {"color": INKS[0], "inks": INKS, "seed": 12345, "path": PATH}
    names, ops = run(page, "tools.js", TOOL_OPS, [types, GESTURE_ENDS, min(CANVAS), more])
    tools = [(t, tool) for t, d in types.items() for tool in DEFINITIONS[t].tools]
    assert names == [tool.name or t for t, tool in tools]
    for (type_, tool), made in zip(tools, ops, strict=True):
        for (a, b), op in zip(GESTURE_ENDS, made, strict=True):
            env = gesture_env(a, b, side=min(CANVAS), scale=1, **more)
            settings = getattr(DEFINITIONS[type_], "settings", ())
            env["setting"] = {s.name: evaluate(s.default, env) for s in settings}
            want = make_op(type_, tool, env)
            assert list(op) == list(want) and _close(op, want), (tool.name or type_, a, b)


STORE = """async () => {
    const m = await import('/web/store.js');
    const seen = [], echoed = [], before = m.get();
    const stop = m.subscribe((s) => [s.probe], (s) => {
        seen.push(s.probe);
        if (s.probe === 2) m.update(() => ({echo: 'two'}));  // a view's update reaches the others
    });
    m.subscribe((s) => [s.echo], (s) => echoed.push(s.echo));
    m.update(() => ({probe: 1}));
    m.update(() => ({probe: 1}));  // the same value: not called
    m.update(() => ({other: 3}));  // a value it does not show: not called
    m.update(() => null);  // no change
    m.update((s) => ({probe: s.probe + 1}));
    stop();
    m.update(() => ({probe: 9}));  // unsubscribed
    return [seen, echoed, before.probe === undefined && m.get().probe === 9, m.get() !== before];
}"""


def test_the_store_calls_a_view_when_what_it_shows_changes(page):
    seen, echoed, kept, replaced = page.evaluate(STORE)
    assert seen == [None, 1, 2]  # once when subscribed, then on each change
    assert echoed == [None, "two"]
    assert kept and replaced  # each update makes a new state; the old one is left as it was


def test_the_actions_table_gives_the_buttons_their_hints(page):
    titles = [page.get_attribute(f"#{name}", "title") for name in ("undo", "redo", "play")]
    assert titles == ["undo (Ctrl-Z)", "redo (Ctrl-Shift-Z, Ctrl-Y)", "play or pause"]
    buttons = page.eval_on_selector_all(
        "#tools button", "bs => bs.map((b) => [b.id, b.dataset.action, b.title])"
    )
    types = describe_ops()
    names = [tool.name or t for t in types for tool in DEFINITIONS[t].tools]
    assert [b[0] for b in buttons] == [f"tool-{n}" for n in names]
    for (id_, action, title), name in zip(buttons, names, strict=True):
        assert action == id_ and title.startswith(f"{name}: ")
    page.click(f"#tool-{names[1]}")
    assert page.evaluate("designer.state.tool") == names[1]
    assert page.eval_on_selector_all("#tools button.on", "bs => bs.map((b) => b.id)") == [
        f"tool-{names[1]}"
    ]
    page.click(f"#tool-{names[0]}")


def test_each_tool_has_its_key_on_its_button_and_in_the_list_of_keys(page):
    tools = [t for d in describe_ops().values() for t in d["tools"]]
    for tool in tools:
        button = f"#tool-{tool['name']}"
        assert page.text_content(f"{button} kbd") == tool["key"]
        assert page.get_attribute(button, "title").endswith(f"({tool['key']})")
        assert tool["hint"] in page.get_attribute(button, "title")
    listed = page.eval_on_selector_all("#keys dt", "ds => ds.map((d) => d.textContent)")
    assert {"Ctrl-Z", "M", "Escape"} <= set(listed) and {t["key"] for t in tools} <= set(listed)
    assert len(listed) == len(set(listed))  # no key twice
    timed = [t["name"] for t in tools if t["gesture"] == "path"]
    assert timed and all("pace drawn" in page.get_attribute(f"#tool-{n}", "title") for n in timed)
    for tool in (tools[-1], tools[0]):
        page.keyboard.press(tool["key"].lower())
        assert page.evaluate("designer.state.tool") == tool["name"]
    clash = run(page, "actions.js", """(m, key) => { try {
        m.register([{name: "probe", keys: [key], hint: "", perform: () => {}}]); return "taken";
    } catch (e) { return String(e); } }""", tools[0]["key"])  # fmt: skip
    assert clash.startswith("Error: actions: key") and tools[0]["name"] in clash


STYLUS = """(m) => {
    const p = m.startPath([0, 0], [100, 100], 1000);
    const took = [
        m.addPoint(p, [0.1, 0], [100.5, 100], 1010),  // under a device pixel: not a point
        m.addPoint(p, [1, 0], [101, 100], 1020),
        m.addPoint(p, [2, 0], [102, 100], 1015),  // an older stamp: its time is not earlier
        m.addPoint(p, [3, 0], [103, 100], 1500.4),
    ];
    const drawn = [m.timesFrom(p, 2.5), m.lastTime(p, 2.5), p.points.length];
    const long = m.startPath([0, 0], [0, 0], 0);
    for (let k = 1; k < m.MAX_POINTS; k++) m.addPoint(long, [k, 0], [k, 0], k);
    const full = long.points.length;
    m.addPoint(long, [m.MAX_POINTS, 0], [m.MAX_POINTS, 0], m.MAX_POINTS);  // one too many
    const times = m.timesFrom(long, 0);
    const rising = times.every((t, k) => k === 0 || t >= times[k - 1]);
    return [took, drawn, full, long.points.length, long.points.at(-1)[0], long.gap, rising];
}"""


def test_a_path_drawn_in_time_takes_a_point_per_device_pixel(page):
    took, drawn, full, halved, newest, gap, rising = run(page, "stylus.js", STYLUS, None)
    assert took == [False, True, True, True]
    assert drawn == [[2.5, 2.52, 2.52, 3.0], 3.0, 4]  # non-decreasing, to the millisecond
    # past MAX_POINTS every other point goes (the first and the newest kept), the gap doubles
    assert full == 4096 and halved == 2049 and newest == 4096 and gap == 2 and rising


def _ops(page) -> list:
    return page.evaluate("designer.state.doc.ops")


def test_a_gesture_goes_idle_pointing_dragging_idle_and_keys_undo_it(page):
    """A drag with the first tool (a click tool) adds its op; a press on the new
    op's handle adds another (a tool never moves an op); in the move mode (M) a
    press on it that moves nothing saves nothing, and with Alt held a drag from it
    moves the point; Esc deselects, after which a press there draws; Ctrl-Z,
    Ctrl-Shift-Z and Delete act on the recipe."""
    box = page.locator("#overlay").bounding_box()

    def at(x: float, y: float) -> tuple[float, float]:
        return box["x"] + x * box["width"] / CANVAS[0], box["y"] + y * box["height"] / CANVAS[1]

    def state(what: str = "designer.gesture.state"):
        return page.evaluate(what)

    assert state() == "idle" and _ops(page) == []
    page.mouse.move(*at(50, 50))
    page.mouse.down()
    assert state() == "pointing tool"
    page.mouse.move(*at(70, 60))
    assert state() == "dragging tool"
    assert state("designer.state.preview.doc.ops.length") == 1  # the sheet shows a draft
    page.mouse.up()
    assert state() == "idle"
    page.wait_for_function("designer.state.doc.ops.length === 1 && designer.state.selected === 0")
    (made,) = _ops(page)
    handles = page.evaluate("designer.handles(0)")
    assert handles, made
    name, point = handles[0]
    page.wait_for_function("designer.state.saving === 0")  # an undo's save may be on its way
    version = state("designer.state.version")

    page.mouse.move(*at(*point))
    page.mouse.down()
    assert state() == "pointing tool"  # a tool's press adds an op, even on a handle
    page.mouse.up()
    page.wait_for_function("designer.state.doc.ops.length === 2")
    page.keyboard.press("Control+z")
    page.wait_for_function("designer.state.doc.ops.length === 1")
    page.click("#op-0 .name")
    page.wait_for_function("designer.state.selected === 0")
    page.wait_for_function("designer.state.saving === 0")  # an undo's save may be on its way
    version = state("designer.state.version")

    page.keyboard.press("m")  # the move mode: a press on a handle takes it
    assert page.evaluate("designer.state.moving") and "on" in page.get_attribute("#move", "class")
    page.mouse.move(*at(*point))
    page.mouse.down()
    assert state() == "pointing handle"
    page.mouse.up()
    assert state() == "idle" and state("designer.state.version") == version  # nothing saved
    page.keyboard.press("m")
    assert not page.evaluate("designer.state.moving")

    page.mouse.move(*at(*point))
    page.keyboard.down("Alt")  # or Alt held for one drag
    page.mouse.down()
    page.mouse.move(*at(point[0] + 20, point[1] + 10))
    assert state() == "dragging handle"
    page.mouse.up()
    page.keyboard.up("Alt")
    page.wait_for_function(f"designer.state.version !== {version}")
    moved = _ops(page)[0]
    assert moved[name] == [point[0] + 20, point[1] + 10] and moved["type"] == made["type"]

    page.keyboard.press("Escape")  # deselects: no handles left to catch a press
    page.wait_for_function("designer.state.selected === null")
    assert page.evaluate("designer.handles(null)") in ([], None)
    page.mouse.move(*at(*point))
    page.mouse.down()
    assert state() == "pointing tool"  # a press where the handle was draws
    page.mouse.up()
    page.wait_for_function("designer.state.doc.ops.length === 2")
    page.keyboard.press("Control+z")
    page.wait_for_function("designer.state.doc.ops.length === 1")

    page.keyboard.press("Control+z")
    page.wait_for_function(f"designer.state.doc.ops[0].{name}[0] === {point[0]}")
    page.keyboard.press("Control+Shift+z")
    page.wait_for_function(f"designer.state.doc.ops[0].{name}[0] === {point[0] + 20}")
    page.click("#op-0 .name")  # selected again from the list, for Delete
    page.wait_for_function("designer.state.selected === 0")
    page.keyboard.press("Delete")
    page.wait_for_function("designer.state.doc.ops.length === 0")
    assert state("designer.state.selected") is None


def test_what_the_fields_show_is_state(page):
    """The loop box, the ink, the palette and the tools' settings are the store's."""
    assert page.evaluate("designer.state.loop") is True
    page.click("#loop")
    assert page.evaluate("designer.state.loop") is False and not page.is_checked("#loop")
    page.evaluate("designer.store.update(() => ({loop: true}))")
    assert page.is_checked("#loop")
    page.select_option("#palettes", "sea")
    assert page.evaluate("[designer.state.palette, designer.state.color]") == ["sea", "#03045e"]
    assert page.input_value("#color") == "#03045e"
    page.click("#palette .swatch:nth-child(2)")
    assert page.evaluate("designer.state.color") == "#0077b6" == page.input_value("#color")
    page.select_option("#palettes", "classic")
    field = page.eval_on_selector("header input[placeholder=auto]", "el => el.id")
    page.fill(f"#{field}", "7")
    assert page.evaluate(f"designer.state.settings['{field}']") == "7"
    page.fill(f"#{field}", "")
    assert page.evaluate(f"designer.state.settings['{field}']") == ""


def test_undo_and_redo_survive_a_reload(page):
    """The stacks are kept in the browser under the file's full path: after a
    reload Ctrl-Z takes back the edit made before it, and after another one
    Ctrl-Shift-Z makes it again."""
    box = page.locator("#overlay").bounding_box()
    x0, y0 = box["x"] + box["width"] * 0.3, box["y"] + box["height"] * 0.4
    before = len(_ops(page))
    page.mouse.move(x0, y0)
    page.mouse.down()
    page.mouse.move(x0 + 15, y0 + 8)
    page.mouse.up()
    page.wait_for_function(f"designer.state.doc.ops.length === {before + 1}")
    stacks = page.evaluate("[designer.state.undo, designer.state.redo]")

    def reloaded():
        page.reload()
        page.wait_for_selector("body[data-ready='1']")

    reloaded()
    assert page.evaluate("[designer.state.undo, designer.state.redo]") == stacks
    page.keyboard.press("Control+z")
    page.wait_for_function(f"designer.state.doc.ops.length === {before}")
    reloaded()
    assert page.evaluate("designer.state.redo.length") == len(stacks[1]) + 1
    page.keyboard.press("Control+Shift+z")
    page.wait_for_function(f"designer.state.doc.ops.length === {before + 1}")
    page.keyboard.press("Control+z")
    page.wait_for_function(f"designer.state.doc.ops.length === {before}")


def test_the_ground_colour_and_clear(page):
    """The ground field shows and sets the recipe's background; Clear removes every
    op in one edit, which Ctrl-Z takes back; neither is enabled for nothing."""
    box = page.locator("#overlay").bounding_box()
    x0, y0 = box["x"] + box["width"] * 0.6, box["y"] + box["height"] * 0.5
    before = page.evaluate("designer.state.doc.ops.length")  # (earlier tests' ops may stay)
    page.mouse.move(x0, y0)
    page.mouse.down()
    page.mouse.move(x0 + 10, y0 + 5)
    page.mouse.up()
    page.wait_for_function(f"designer.state.doc.ops.length === {before + 1}")
    ops = _ops(page)
    assert page.input_value("#ground") == page.evaluate("designer.state.doc.background").lower()
    page.fill("#ground", "#204060")  # the field's value and its change event
    page.wait_for_function("designer.state.doc.background === '#204060'")
    assert page.evaluate("designer.state.doc.ops") == ops

    assert page.is_enabled("#clear") and "undoable" in page.get_attribute("#clear", "title")
    page.click("#clear")
    page.wait_for_function("designer.state.doc.ops.length === 0")
    assert page.evaluate("designer.state.selected") is None and page.is_disabled("#clear")
    assert page.evaluate("designer.state.doc.background") == "#204060"  # the ground stays
    page.keyboard.press("Control+z")
    page.wait_for_function(f"designer.state.doc.ops.length === {len(ops)}")
    page.keyboard.press("Control+z")  # and the ground goes back too
    page.wait_for_function("designer.state.doc.background !== '#204060'")


def test_two_clicks_at_one_centre_make_two_concentric_drops(page):
    """The trap that made a tulip's second drop move the first is gone: a click on
    the new drop's centre (its handle) adds a drop there."""
    page.click("[data-action='tool-drop']")
    box = page.locator("#overlay").bounding_box()
    x, y = box["x"] + box["width"] * 0.25, box["y"] + box["height"] * 0.75
    before = len(_ops(page))
    for n in (1, 2):
        page.mouse.click(x, y)
        page.wait_for_function(f"designer.state.doc.ops.length === {before + n}")
    first, second = _ops(page)[before:]
    assert first["type"] == second["type"] == "drop"
    assert first["center"] == second["center"]
    for _ in (1, 2):
        page.keyboard.press("Control+z")
    page.wait_for_function(f"designer.state.doc.ops.length === {before}")
