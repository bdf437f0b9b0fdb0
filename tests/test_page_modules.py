"""The page's ES modules (marblevideo/design/web) unit-tested in a real headless
Chromium, loaded from the real designer's server (``/web/NAME``) and checked
against Python on vectors Python makes: the easing (ease.js against
marblevideo.recipe.keyframes.ease), the slider ranges (range.js on /api/ops's
laws against marblevideo.ops.slider_range), and the tool table and the ops its
tools make (tools.js on /api/ops against marblevideo.ops.gestures). One server
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
