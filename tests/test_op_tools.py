"""The designer's tools and ``GET /api/ops`` as the op definitions state them:
every tool of every type makes an op the recipe format accepts (a click and
drags every way, in Python's evaluation of the tool expressions, which the
page's tools.js mirrors: tests/test_page_modules.py), the description holds
every registered type and parameter, the page's sources name no op type, and
``/web/NAME`` serves only plain names of known types."""

from __future__ import annotations

import re

import pytest

from marblevideo.design.describe import describe_ops
from marblevideo.design.session import WEB
from marblevideo.ops import LAYOUTS, REGISTRY, recipe_types
from marblevideo.ops.base import slider_range, slider_spec, spec_range
from marblevideo.ops.gestures import GESTURES, evaluate, gesture_env, make_op
from marblevideo.recipe import parse_recipe
from marblevideo.serve.server import static_file

pytestmark = pytest.mark.tier("fast")

CANVAS = (400, 300)
SCALE = 1.5  # frame pixels per canvas unit
PATH = [[60.0, 200.0], [120.0, 150.5], [180.0, 210.0], [240.0, 160.0]]
#: (a, b) gestures: a click, then drags every way.
GESTURE_ENDS = [
    ((200, 150), (200, 150)),
    ((100, 80), (260, 220)),
    ((300, 250), (120, 40.5)),
    ((50, 150), (50, 10)),
]
DEFINITIONS = {**REGISTRY, **LAYOUTS}
TOOLS = [(t, tool) for t, d in DEFINITIONS.items() for tool in d.tools]


def env_for(definition, a, b, seed: int = 7) -> dict:
    """A gesture's measures with the definition's settings at their defaults."""
    env = gesture_env(
        a,
        b,
        side=min(CANVAS),
        scale=SCALE,
        color="#1d3557",
        inks=["#1d3557", "#b23a48", "#e9c46a"],
        seed=seed,
        path=PATH,
    )
    settings = getattr(definition, "settings", ())
    return {**env, "setting": {s.name: evaluate(s.default, env) for s in settings}}


@pytest.mark.parametrize(("type_", "tool"), TOOLS, ids=[t.name or k for k, t in TOOLS])
def test_every_tool_makes_a_valid_op(type_, tool):
    definition = DEFINITIONS[type_]
    names = {p.name for p in definition.params}
    assert tool.gesture in GESTURES and set(tool.make) <= names
    assert tool.label is None or tool.label in tool.make
    for a, b in GESTURE_ENDS:
        op = make_op(type_, tool, env_for(definition, a, b))
        parse_recipe({"canvas": list(CANVAS), "ops": [op]})  # raises when invalid


def test_a_click_and_a_drag_measure_as_the_docstring_says():
    env = gesture_env((10, 20), (10.5, 20), side=300, scale=2.0)
    assert env["clicked"] and (env["dx"], env["dy"], env["len"]) == (30, 0, 30)
    assert env["tip"] == [40, 20] and env["angle"] == 0
    env = gesture_env((10, 20), (10, 60), side=300, scale=2.0)
    assert not env["clicked"] and env["len"] == 40 and env["angle"] == 90


def test_every_type_is_described_with_its_parameters_and_tools():
    described = describe_ops()
    assert sorted(described) == sorted(recipe_types())
    for type_, d in described.items():
        definition = DEFINITIONS[type_]
        names = [p["name"] for p in d["params"]]
        assert names == [p.name for p in definition.params] + ["start", "end"]
        assert [t["name"] for t in d["tools"]] == [t.name or type_ for t in definition.tools]
        assert d.get("layout", False) == (type_ in LAYOUTS)
        for p in d["params"]:
            if p["slider"] is not None:
                param = next((q for q in definition.params if q.name == p["name"]), None)
                spec = {**p["range"], "units": p["units"]}
                if param is not None:  # not start or end
                    assert spec == slider_spec(param)
                    assert spec_range(spec, 33.3, 640) == slider_range(param, 33.3, 640)
    assert described["scatter-drops"]["params"][6]["choices"] == ["uniform", "normal"]
    assert not described["shift"]["params"][0]["handle"]  # a motion, not a place


def test_every_tool_has_its_own_key_and_a_hint():
    """One letter each, none twice, none of the page's own keys (M: the move
    mode; Z and Y: undo and redo with Ctrl), and a one-line hint."""
    tools = [t for d in describe_ops().values() for t in d["tools"]]
    keys = [t["key"] for t in tools]
    assert all(len(k) == 1 and "A" <= k <= "Z" for k in keys), keys
    assert len(set(keys)) == len(keys) and not set(keys) & {"M", "Z", "Y"}
    assert all(t["hint"] and "\n" not in t["hint"] and len(t["hint"]) < 80 for t in tools)


def test_the_pages_sources_name_no_op_type():
    """The warp (warp*.js) is exempt: it is the page's float32 copy of the
    kernels (kernels/ops/*.cl), one inverse per op type as they have, and
    tests/test_warp_browser.py checks it knows every type."""
    types = "|".join(re.escape(t) for t in recipe_types())
    quoted = re.compile(rf"""["'`]({types})["'`]""")
    sources = sorted(WEB.glob("*.js")) + sorted(WEB.glob("*.html"))
    sources = [p for p in sources if not p.name.startswith("warp")]
    assert len(sources) > 5
    named = {p.name: quoted.findall(p.read_text()) for p in sources}
    assert {k: v for k, v in named.items() if v} == {}


def test_web_files_are_plain_names_of_known_types(tmp_path):
    (tmp_path / "a.js").write_text("export const a = 1;\n")
    (tmp_path / "notes.txt").write_text("x")
    (tmp_path / ".hidden.js").write_text("x")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.js").write_text("x")
    assert static_file(tmp_path, "/web/a.js") == (
        b"export const a = 1;\n",
        "text/javascript; charset=utf-8",
    )
    for path in (
        "/web/notes.txt",
        "/web/.hidden.js",
        "/web/sub/b.js",
        "/web/../a.js",
        "/web/%2e%2e/a.js",
        "/web/missing.js",
        "/a.js",
        "/web/",
    ):
        assert static_file(tmp_path, path) is None, path
    assert static_file(None, "/web/a.js") is None
    body, ctype = static_file(WEB, "/web/main.js")
    assert ctype.startswith("text/javascript") and b"import" in body
