"""Recipe loading, validation messages, the model, and the published schema."""

from __future__ import annotations

import copy
import json
import math

import jsonschema
import numpy as np
import pytest

from marblevideo.errors import RecipeError, UsageError
from marblevideo.ops import REGISTRY, recipe_types
from marblevideo.recipe import Op, Recipe, load_recipe, parse_recipe
from marblevideo.recipe.frame import FrameSpec
from marblevideo.recipe.keyframes import EASE_NAMES
from marblevideo.recipe.schema import schema

pytestmark = pytest.mark.tier("fast")

OPS = {
    "drop": {"type": "drop", "center": [10, 20], "radius": 5, "color": "#ff8000"},
    "spray": {"type": "spray", "center": [1.5, 2], "radius": 0.5, "color": [0, 128, 255]},
    "tine": {"type": "tine", "point": [0, 50], "angle": 90, "alpha": -30, "lambda": 8},
    "comb": {"type": "comb", "point": [0, 0], "angle": 0, "spacing": 20, "alpha": 10, "lambda": 4},
    "wave": {"type": "wave", "amplitude": 5, "wavelength": 40, "phase": 30, "angle": 45},
    "circle": {"type": "circle", "center": [50, 50], "radius": 0, "alpha": 60, "lambda": 10},
    "vortex": {"type": "vortex", "center": [50, 50], "alpha": 200, "lambda": 25},
}


def recipe_with(*ops: dict, **top) -> dict:
    return {"canvas": [100, 80], "ops": [copy.deepcopy(op) for op in ops], **top}


def fault(data: object) -> str:
    with pytest.raises(RecipeError) as info:
        parse_recipe(data, "swirl.json")
    return str(info.value)


def op_fault(op: dict, **changes) -> str:
    op = {**copy.deepcopy(op), **changes}
    return fault(recipe_with(OPS["drop"], op))


# ---------------------------------------------------------------- valid recipes


@pytest.mark.parametrize("name", list(OPS))
def test_every_op_parses_with_the_contract_param_names(name):
    recipe = parse_recipe(recipe_with(OPS[name]), "x.json")
    (op,) = recipe.ops
    assert op.type == name and op.index == 0 and op.start is None and op.end is None
    assert tuple(op.params) == tuple(REGISTRY[name].kinds)
    state = recipe.at(0.0).ops[0]
    assert tuple(state.values) == tuple(REGISTRY[name].kinds)
    for param, value in OPS[name].items():
        if param == "type":
            continue
        got = state[param]
        if isinstance(value, list):
            assert got == tuple(float(c) for c in value)
        elif isinstance(value, str):
            assert got == (255.0, 128.0, 0.0)
        else:
            assert got == float(value) and isinstance(got, float)


def test_defaults_and_top_level_fields():
    recipe = parse_recipe({"ops": []}, "x.json")
    assert recipe.ops == () and recipe.canvas is None
    assert recipe.antialias == "rgss" and recipe.edges == "clamp" and recipe.source == "x.json"
    frame = recipe.at(0.0, canvas=(640, 360))
    assert frame == FrameSpec((), (255.0, 255.0, 255.0), "rgss", "clamp", (640.0, 360.0))
    full = {
        "$schema": "./recipe.schema.json",
        "marblevideo": 1,
        "canvas": [4.5, 3],
        "background": [1, 2, 3],
        "antialias": "rooks8",
        "edges": "mirror",
        "ops": [],
    }
    recipe = parse_recipe(full, "x.json")
    assert recipe.canvas == (4.5, 3.0) and recipe.antialias == "rooks8" and recipe.edges == "mirror"
    assert recipe.at(0).background == (1.0, 2.0, 3.0)
    assert recipe.at(0, canvas=(9, 9)).canvas == (4.5, 3.0)  # the recipe's canvas wins


def test_python_api_accepts_tuples_and_from_dict():
    data = {"ops": [{**OPS["drop"], "center": (3, 4), "color": (1, 2, 3)}], "canvas": (10, 10)}
    recipe = Recipe.from_dict(data)
    assert recipe.source == "<dict>" and recipe.at(0).ops[0]["center"] == (3.0, 4.0)
    numpy_values = {**OPS["drop"], "center": np.array([3.0, 4.0]).tolist(), "radius": np.int64(2)}
    numpy_values["color"] = tuple(np.array([1, 2, 3], dtype=np.uint8))
    state = parse_recipe(recipe_with(numpy_values)).at(0).ops[0]
    assert state["radius"] == 2.0 and state["color"] == (1.0, 2.0, 3.0)
    with pytest.raises(
        RecipeError, match=r"radius: expected a number or a keyframe track \{.*\}, got NaN"
    ):
        parse_recipe(recipe_with({**OPS["drop"], "radius": np.float32("nan")}))


def test_no_canvas_anywhere_is_a_usage_error():
    recipe = parse_recipe({"ops": []}, "x.json")
    with pytest.raises(UsageError, match="no canvas"):
        recipe.at(0.0)


@pytest.mark.parametrize("ease", [*EASE_NAMES, [0.25, 0.1, 0.25, 1.0], [0, -0.5, 1, 1.5]])
def test_every_ease_parses(ease):
    track = {"keys": [{"t": 0, "v": 1, "ease": ease}, {"t": 2, "v": 3}]}
    recipe = parse_recipe(recipe_with({**OPS["tine"], "alpha": track}), "x.json")
    expected = ease if isinstance(ease, str) else tuple(float(c) for c in ease)
    assert recipe.ops[0].params["alpha"].keys[0].ease == expected
    assert recipe.at(0).ops[0]["alpha"] == 1.0 and recipe.at(2).ops[0]["alpha"] == 3.0


def test_keyed_points_colors_and_background():
    center = {"keys": [{"t": 0, "v": [0, 0]}, {"t": 2, "v": [10, 40]}]}
    color = {"keys": [{"t": 0, "v": "#000000"}, {"t": 2, "v": [255, 255, 0], "ease": "hold"}]}
    background = {"keys": [{"t": 1, "v": [0, 0, 0]}, {"t": 3, "v": "#ff0000"}]}
    data = recipe_with({**OPS["drop"], "center": center, "color": color}, background=background)
    recipe = parse_recipe(data, "x.json")
    frame = recipe.at(1.0)
    assert frame.ops[0]["center"] == (5.0, 20.0)
    assert frame.ops[0]["color"] == (127.5, 127.5, 0.0)
    assert frame.background == (0.0, 0.0, 0.0)
    assert recipe.at(2.0).background == (127.5, 0.0, 0.0)
    assert recipe.end_time() == 3.0 and recipe.is_animated


# ---------------------------------------------------------------- progress and time


def make_op(start, end) -> Op:
    return parse_recipe(recipe_with({**OPS["tine"], "start": start, "end": end}), "x").ops[0]


def test_progress_neither_start_nor_end():
    op = parse_recipe(recipe_with(OPS["tine"]), "x").ops[0]
    assert [op.progress(t) for t in (-5, 0, 100)] == [1.0, 1.0, 1.0]


def test_progress_start_only_jumps():
    op = parse_recipe(recipe_with({**OPS["tine"], "start": 2}), "x").ops[0]
    assert (op.start, op.end) == (2.0, None)
    assert [op.progress(t) for t in (0, 1.999, 2, 5)] == [0.0, 0.0, 1.0, 1.0]


def test_progress_start_and_end_ramps():
    op = make_op(1, 3)
    assert [op.progress(t) for t in (0, 0.999, 1, 2, 2.5, 3, 10)] == [0, 0, 0, 0.5, 0.75, 1, 1]


def test_at_applies_progress_scaling():
    ops = [{**OPS[name], "start": 0, "end": 4} for name in OPS]
    frame = parse_recipe(recipe_with(*ops), "x").at(1.0)  # p = 1/4
    by_type = {state.type: state for state in frame.ops}
    assert by_type["drop"]["radius"] == pytest.approx(5 * 0.5)  # r * sqrt(p)
    assert by_type["spray"]["radius"] == pytest.approx(0.5 * 0.5)
    assert by_type["tine"]["alpha"] == pytest.approx(-30 / 4)
    assert by_type["comb"]["alpha"] == pytest.approx(10 / 4)
    assert by_type["circle"]["alpha"] == pytest.approx(60 / 4)
    assert by_type["vortex"]["alpha"] == pytest.approx(200 / 4)
    assert by_type["wave"]["amplitude"] == pytest.approx(5 / 4)
    # Nothing else is scaled.
    assert by_type["tine"]["lambda"] == 8.0 and by_type["wave"]["wavelength"] == 40.0
    assert by_type["drop"]["color"] == (255.0, 128.0, 0.0)
    before = parse_recipe(recipe_with(*ops), "x").at(-1.0)
    assert before.ops[0]["radius"] == 0.0 and before.ops[2]["alpha"] == 0.0


def test_end_time():
    assert parse_recipe(recipe_with(OPS["drop"]), "x").end_time() == 0.0
    assert not parse_recipe(recipe_with(OPS["drop"]), "x").is_animated
    assert parse_recipe(recipe_with({**OPS["drop"], "start": 1.5}), "x").end_time() == 1.5
    keyed = {**OPS["vortex"], "alpha": {"keys": [{"t": 0.5, "v": 0}, {"t": 7, "v": 90}]}}
    recipe = parse_recipe(recipe_with(keyed, {**OPS["drop"], "start": 2, "end": 6}), "x")
    assert recipe.end_time() == 7.0
    recipe = parse_recipe(recipe_with(OPS["drop"], background={"keys": [{"t": 9, "v": "#000000"}]}))
    assert recipe.end_time() == 9.0


# ---------------------------------------------------------------- faults, one per class


def test_fault_message_shape_from_the_contract():
    message = op_fault(OPS["tine"], **{"lambda": -2})
    assert message == "swirl.json: ops[1].lambda: must be > 0, got -2"


@pytest.mark.parametrize(
    ("name", "param", "bad", "expected"),
    [
        ("drop", "radius", 0, "must be > 0, got 0"),
        ("spray", "radius", -1.5, "must be > 0, got -1.5"),
        ("comb", "spacing", 0, "must be > 0, got 0"),
        ("comb", "lambda", -1, "must be > 0, got -1"),
        ("wave", "wavelength", -3, "must be > 0, got -3"),
        ("circle", "radius", -0.5, "must be >= 0, got -0.5"),
        ("vortex", "lambda", 0, "must be > 0, got 0"),
    ],
)
def test_out_of_range(name, param, bad, expected):
    assert op_fault(OPS[name], **{param: bad}) == f"swirl.json: ops[1].{param}: {expected}"


def test_circle_radius_zero_is_allowed():
    parse_recipe(recipe_with({**OPS["circle"], "radius": 0}), "x")


def test_wrong_types():
    assert op_fault(OPS["tine"], angle="abc") == (
        'swirl.json: ops[1].angle: expected a number or a keyframe track {"keys": [...]} '
        'or a signal {"signal": NAME, "range": [lo, hi]}, '
        "got string 'abc'"
    )
    assert op_fault(OPS["tine"], point=[1, "2"]) == (
        "swirl.json: ops[1].point[1]: expected a number, got string '2'"
    )
    assert op_fault(OPS["tine"], point=[1, 2, 3]) == (
        "swirl.json: ops[1].point: expected a point [x, y], got a list of 3"
    )
    assert fault({"ops": {}}) == "swirl.json: ops: expected a list, got an object"
    assert fault([1]) == "swirl.json: expected a marblevideo recipe, got a list of 1"
    assert fault({"ops": [3]}) == "swirl.json: ops[0]: expected an object, got 3"


def test_booleans_are_not_numbers():
    assert op_fault(OPS["tine"], alpha=True).startswith("swirl.json: ops[1].alpha: expected a num")
    assert op_fault(OPS["drop"], center=[1, False]) == (
        "swirl.json: ops[1].center[1]: expected a number, got false"
    )


@pytest.mark.parametrize(
    ("color", "path", "expected"),
    [
        ("#ff00", "color", 'expected "#rrggbb" or "#rgb" (hex digits), got string \'#ff00\''),
        ("#gg0000", "color", 'expected "#rrggbb" or "#rgb" (hex digits), got string \'#gg0000\''),
        ([0, 0, 256], "color[2]", "must be <= 255, got 256"),
        ([0, -1, 0], "color[1]", "must be >= 0, got -1"),
        ([0, 1.5, 0], "color[1]", "expected an integer, got 1.5"),
        ([0, 0], "color", "expected a color [r, g, b], got a list of 2"),
        (
            7,
            "color",
            'expected a color ("#rrggbb", "#rgb", a CSS color name or [r, g, b]) '
            'or a keyframe track {"keys": [...]}, got 7',
        ),
    ],
)
def test_bad_colors(color, path, expected):
    assert op_fault(OPS["spray"], color=color) == f"swirl.json: ops[1].{path}: {expected}"


def test_bad_background_and_canvas():
    assert fault(recipe_with(background="whit")).startswith(
        "swirl.json: background: unknown color 'whit' (did you mean 'white'?)"
    )
    assert fault({"canvas": [0, 10], "ops": []}) == "swirl.json: canvas[0]: must be >= 1e-30, got 0"
    # a side so small that pixels per unit overflow (5e-324: the API fuzz's SVG crash)
    tiny = fault({"canvas": [9, 5e-324], "ops": []})
    assert tiny.endswith("canvas[1]: must be >= 1e-30, got 5e-324")
    assert fault({"canvas": [10], "ops": []}) == (
        "swirl.json: canvas: expected a size [W, H], got a list of 1"
    )


def test_unknown_op_type_suggests():
    assert op_fault({"type": "dorp"}) == (
        "swirl.json: ops[1].type: unknown op type 'dorp' (did you mean 'drop'?); "
        f"expected one of {', '.join(recipe_types())}"
    )


def test_unknown_fields_suggest():
    op = {k: v for k, v in OPS["tine"].items() if k != "lambda"}
    assert op_fault({**op, "lamda": 3}) == (
        "swirl.json: ops[1]: unknown field 'lamda' (did you mean 'lambda'?)"
    )
    assert fault({"ops": [], "antialais": "none"}) == (
        "swirl.json: unknown field 'antialais' (did you mean 'antialias'?)"
    )
    track = {"keys": [{"t": 0, "v": 1, "eas": "hold"}]}
    assert op_fault(OPS["tine"], alpha=track) == (
        "swirl.json: ops[1].alpha.keys[0]: unknown field 'eas' (did you mean 'ease'?)"
    )


@pytest.mark.parametrize("name", list(OPS))
def test_missing_required_fields(name):
    for param in REGISTRY[name].kinds:
        op = {k: v for k, v in OPS[name].items() if k != param}
        assert op_fault(op) == f"swirl.json: ops[1]: missing required field '{param}'"
    assert fault({"canvas": [1, 1]}) == "swirl.json: missing required field 'ops'"
    assert op_fault({"center": [1, 2]}, type=None).startswith("swirl.json: ops[1].type: ")
    no_type = {k: v for k, v in OPS["drop"].items() if k != "type"}
    assert op_fault(no_type) == "swirl.json: ops[1]: missing required field 'type'"


def test_version_other_than_1():
    assert fault({"marblevideo": 2, "ops": []}) == (
        "swirl.json: marblevideo: unsupported recipe format version: expected 1, got 2"
    )
    assert fault({"marblevideo": "1", "ops": []}).startswith("swirl.json: marblevideo: expected")


def test_enums_suggest():
    assert fault({"ops": [], "antialias": "rgs"}) == (
        "swirl.json: antialias: unknown antialias pattern 'rgs' (did you mean 'rgss'?); "
        "expected one of none, rgss, quincunx, checker4, grid4, rooks8"
    )
    assert fault({"ops": [], "edges": "wrap"}).startswith(
        "swirl.json: edges: unknown edge mode 'wrap'; expected one of clamp, repeat, mirror"
    )


def test_key_times_must_increase_strictly():
    keys = [{"t": 0, "v": [0, 0]}, {"t": 1, "v": [1, 1]}, {"t": 1, "v": [2, 2]}]
    assert op_fault(OPS["drop"], center={"keys": keys}) == (
        "swirl.json: ops[1].center.keys[2].t: key times must increase strictly: got 1 after 1"
    )


def test_bad_tracks():
    assert op_fault(OPS["drop"], radius={"keys": []}) == (
        "swirl.json: ops[1].radius.keys: expected at least 1 item, got an empty list"
    )
    wrong_kind = {"keys": [{"t": 0, "v": 1}, {"t": 1, "v": [1, 2]}]}
    assert op_fault(OPS["drop"], radius=wrong_kind) == (
        "swirl.json: ops[1].radius.keys[1].v: expected a number, got a list of 2"
    )
    negative = {"keys": [{"t": 0, "v": 1}, {"t": 1, "v": -1}]}
    assert op_fault(OPS["drop"], radius=negative) == (
        "swirl.json: ops[1].radius.keys[1].v: must be > 0, got -1"
    )
    assert op_fault(OPS["drop"], radius={"keys": [{"t": 0}]}) == (
        "swirl.json: ops[1].radius.keys[0]: missing required field 'v'"
    )
    assert op_fault(OPS["drop"], radius={"kyes": []}) == (
        "swirl.json: ops[1].radius: unknown field 'kyes' (did you mean 'keys'?)"
    )
    bad_t = {"keys": [{"t": "0", "v": 1}]}
    assert op_fault(OPS["drop"], radius=bad_t) == (
        "swirl.json: ops[1].radius.keys[0].t: expected a number, got string '0'"
    )


@pytest.mark.parametrize(
    ("ease", "path", "expected"),
    [
        ("ease-inout", "ease", "unknown ease name 'ease-inout' (did you mean 'ease-in-out'?)"),
        ([1.2, 0, 1, 1], "ease[0]", "must be <= 1, got 1.2"),
        ([0, 0, -0.1, 1], "ease[2]", "must be >= 0, got -0.1"),
        ([0, 0, 1], "ease", "expected a cubic-bezier [x1, y1, x2, y2], got a list of 3"),
        (3, "ease", "expected an ease name or a cubic-bezier [x1, y1, x2, y2], got 3"),
    ],
)
def test_bad_eases(ease, path, expected):
    track = {"keys": [{"t": 0, "v": 1, "ease": ease}, {"t": 1, "v": 2}]}
    message = op_fault(OPS["vortex"], alpha=track)
    assert message.startswith(f"swirl.json: ops[1].alpha.keys[0].{path}: {expected}")


def test_start_and_end():
    assert op_fault(OPS["drop"], start=2, end=2) == (
        "swirl.json: ops[1].end: must be > start (2), got 2"
    )
    assert op_fault(OPS["drop"], start=2, end=1.5).startswith("swirl.json: ops[1].end: must be >")
    assert op_fault(OPS["drop"], end=2) == (
        "swirl.json: ops[1]: 'end' requires 'start' (progress runs from start to end)"
    )
    assert op_fault(OPS["drop"], start="soon") == (
        "swirl.json: ops[1].start: expected a number, got string 'soon'"
    )


def test_non_finite_and_huge_numbers_from_python():
    assert op_fault(OPS["drop"], radius=math.nan) == (
        'swirl.json: ops[1].radius: expected a number or a keyframe track {"keys": [...]} '
        'or a signal {"signal": NAME, "range": [lo, hi]}, '
        "got NaN (not a finite number)"
    )
    assert op_fault(OPS["drop"], center=[0, -math.inf]) == (
        "swirl.json: ops[1].center[1]: expected a number, got -Infinity (not a finite number)"
    )
    assert op_fault(OPS["tine"], alpha=1e31) == (
        "swirl.json: ops[1].alpha: too large: must be within -1e30..1e30 (float32 range), got 1e+31"
    )


def test_first_fault_in_document_order():
    ops = [OPS["drop"], {**OPS["tine"], "lambda": -1, "angle": "x"}, {"type": "nope"}]
    assert fault({"ops": ops, "edges": "bad"}).startswith("swirl.json: ops[1].angle: ")
    assert fault({"edges": "bad", "ops": ops}).startswith("swirl.json: edges: ")
    # The same op with its keys in another order reports the other, now earlier, fault.
    tine = {"lambda": -1, **OPS["tine"], "angle": "x"}
    tine["lambda"] = -1
    assert fault({"ops": [tine]}).startswith("swirl.json: ops[0].lambda: ")
    unknown_then_missing = {"type": "vortex", "centre": [1, 2], "alpha": 1, "lambda": 1}
    assert fault({"ops": [unknown_then_missing]}) == (
        "swirl.json: ops[0]: unknown field 'centre' (did you mean 'center'?)"
    )


# ---------------------------------------------------------------- files


def write(tmp_path, text: str, name: str = "swirl.json"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_load_recipe_reads_a_file_and_names_it(tmp_path):
    path = write(tmp_path, "\ufeff" + json.dumps(recipe_with(OPS["comb"])))  # BOM is fine
    recipe = load_recipe(path)
    assert recipe.source == str(path) and recipe.ops[0].type == "comb"


def test_invalid_json_names_line_and_column(tmp_path):
    path = write(tmp_path, '{\n  "ops": [\n    {"type": "drop" "center": [1, 2]}\n  ]\n}\n')
    with pytest.raises(RecipeError) as info:
        load_recipe(path)
    assert str(info.value) == (
        f"{path}: invalid JSON at line 3, column 21: Expecting ',' delimiter"
    )


@pytest.mark.parametrize(
    ("literal", "got"),
    [("NaN", "NaN"), ("Infinity", "Infinity"), ("-Infinity", "-Infinity"), ("1e400", "1e400")],
)
def test_non_finite_literals_are_refused_where_they_are(tmp_path, literal, got):
    text = json.dumps(recipe_with(OPS["tine"])).replace('"alpha": -30', f'"alpha": {literal}')
    with pytest.raises(RecipeError) as info:
        load_recipe(write(tmp_path, text))
    assert info.value.path == "ops[0].alpha"
    assert str(info.value).endswith(f"got {got} (not a finite number)")


def test_missing_or_unreadable_file_is_a_one_line_usage_error(tmp_path):
    for path in (tmp_path / "nope.json", tmp_path):
        with pytest.raises(UsageError) as info:
            load_recipe(path)
        assert not isinstance(info.value, RecipeError)
        assert str(info.value).startswith(f"cannot read recipe {path}: ")
        assert "\n" not in str(info.value)
    bad = tmp_path / "latin1.json"
    bad.write_bytes(b'{"ops": [], "x": "\xe9"}')
    with pytest.raises(UsageError, match="cannot read recipe"):
        load_recipe(bad)


# ---------------------------------------------------------------- the published schema


VALID_SAMPLES = [
    {"ops": []},
    recipe_with(*OPS.values()),
    recipe_with(
        {**OPS["drop"], "start": 0, "end": 2},
        {**OPS["wave"], "phase": {"keys": [{"t": 0, "v": 0, "ease": [0.3, -1, 0.7, 2]}]}},
        background={"keys": [{"t": 0, "v": "#000000", "ease": "hold"}, {"t": 1, "v": [9, 9, 9]}]},
        antialias="grid4",
        edges="background",
        marblevideo=1,
    ),
]

INVALID_SAMPLES = [
    {},
    {"ops": [{"type": "dorp"}]},
    {"ops": [{**OPS["tine"], "lamda": 1}]},
    {"ops": [{**OPS["tine"], "lambda": 0}]},
    {"ops": [{**OPS["drop"], "end": 1}]},
    {"ops": [{**OPS["drop"], "color": "#12345"}]},
    {"ops": [{**OPS["drop"], "color": [1, 2, 256]}]},
    {"ops": [{**OPS["drop"], "radius": {"keys": []}}]},
    {"ops": [{**OPS["drop"], "radius": {"keys": [{"t": 0, "v": 1, "ease": "bounce"}]}}]},
    {"ops": [{**OPS["circle"], "radius": -1}]},
    {"ops": [{**OPS["comb"], "spacing": True}]},
    {"ops": [], "marblevideo": 2},
    {"ops": [], "antialias": "msaa"},
    {"ops": [], "canvas": [1, 2, 3]},
]


def test_schema_is_a_valid_draft_2020_12_schema():
    doc = schema()
    jsonschema.Draft202012Validator.check_schema(doc)
    assert doc["$schema"] == "https://json-schema.org/draft/2020-12/schema" and doc["$id"]
    assert set(REGISTRY) <= set(doc["$defs"])
    for name, params in ((n, tuple(d.kinds)) for n, d in REGISTRY.items()):
        props = doc["$defs"][name]["properties"]
        assert set(props) == {"type", "start", "end", "heal", "hidden", *params}
        assert all(props[p]["description"] for p in params)
    json.dumps(doc)  # printable as JSON
    doc["title"] = "changed"
    assert schema()["title"] != "changed"  # callers get a copy


@pytest.mark.parametrize("sample", VALID_SAMPLES)
def test_valid_samples_pass_plain_jsonschema_and_the_loader(sample):
    jsonschema.validate(sample, schema(), cls=jsonschema.Draft202012Validator)
    parse_recipe(sample, "x.json")


@pytest.mark.parametrize("sample", INVALID_SAMPLES)
def test_invalid_samples_fail_plain_jsonschema_and_the_loader(sample):
    assert not jsonschema.Draft202012Validator(schema()).is_valid(sample)
    with pytest.raises(RecipeError):
        parse_recipe(sample, "x.json")


def test_non_identifier_keys_use_bracket_paths():
    """A key like '²' (isalnum() is True for it) or '1x' is quoted in the JSON path."""
    deep: list = []
    for _ in range(40):
        deep = [deep]
    with pytest.raises(RecipeError) as err:
        parse_recipe({"marblevideo": 1, "ops": [], "²": deep}, "odd.json")
    assert err.value.path.startswith('["²"][0][0]')


def test_a_key_given_twice_is_refused_where_it_is(tmp_path):
    text = json.dumps(recipe_with(OPS["tine"])).replace('"alpha": -30', '"alpha": -30, "alpha": 5')
    with pytest.raises(RecipeError) as info:
        load_recipe(write(tmp_path, text))
    assert info.value.path == "ops[0].alpha"
    assert str(info.value) == (
        f"{tmp_path / 'swirl.json'}: ops[0].alpha: given twice in one object "
        "(JSON would keep only the last)"
    )
    top = '{"marblevideo": 1, "ops": [], "ops": []}'
    with pytest.raises(RecipeError, match=r": ops: given twice"):
        load_recipe(write(tmp_path, top))


# ---------------------------------------------------------------- hidden ops


def test_hidden_ops_stay_in_the_file_and_out_of_the_render():
    rings = {"type": "rings", "center": [50, 40], "count": 2, "width": 4, "colors": ["#102030"]}
    doc = recipe_with(
        OPS["drop"],
        {**OPS["tine"], "hidden": True},
        {**rings, "hidden": True},
        rings,
        {**OPS["wave"], "hidden": False},
    )
    recipe = parse_recipe(doc, "r.json")
    assert [op.type for op in recipe.ops] == ["drop", "drop", "drop", "wave"]
    assert [op.index for op in recipe.ops] == [0, 1, 2, 3]
    assert [op.entry for op in recipe.ops] == [0, 3, 3, 4]
    assert [op.layout for op in recipe.ops] == [None, ("rings", 3), ("rings", 3), None]
    assert recipe.entries == 5
    shown = parse_recipe(recipe_with(OPS["drop"], rings, OPS["wave"]), "r.json")
    assert recipe.at(1.0) == shown.at(1.0)
    # a hidden keyed op does not animate the recipe
    keyed = {**OPS["tine"], "alpha": {"keys": [{"t": 0, "v": 1}, {"t": 9, "v": 5}]}}
    assert parse_recipe(recipe_with(OPS["drop"], keyed), "r.json").end_time() == 9
    hidden = parse_recipe(recipe_with(OPS["drop"], {**keyed, "hidden": True}), "r.json")
    assert not hidden.is_animated and hidden.end_time() == 0


def test_hidden_is_a_boolean_and_a_hidden_op_must_still_be_valid():
    assert op_fault(OPS["tine"], hidden="yes") == (
        "swirl.json: ops[1].hidden: expected true or false, got string 'yes'"
    )
    assert op_fault(OPS["tine"], hidden=True, **{"lambda": -1}) == (
        "swirl.json: ops[1].lambda: must be > 0, got -1"
    )
    assert parse_recipe(recipe_with({**OPS["drop"], "hidden": True}), "r.json").ops == ()
    defs = schema()["$defs"]
    for name in ("tine", "rings"):
        assert defs[name]["properties"]["hidden"]["type"] == "boolean"
