"""Colours: everywhere a recipe takes a colour it reads "#rrggbb",
"#rgb", a CSS color name in any case, or [r, g, b]; a near miss is one line with
its JSON path and a did-you-mean, from the command line and from the API."""

from __future__ import annotations

import json
import os

import cv2
import pytest
import webcolors
from helpers import one_line
from jsonschema import Draft202012Validator

from marblevideo import RecipeError, parse_recipe, render_image
from marblevideo.recipe.schema import schema

pytestmark = pytest.mark.tier("fast")

SHAPES = '"#rrggbb", "#rgb", a CSS color name or [r, g, b]'


def drop(color) -> dict:
    return {"type": "drop", "center": [8, 6], "radius": 4, "color": color}


def recipe(*ops, **top) -> dict:
    return {"canvas": [16, 12], "antialias": "none", "ops": list(ops), **top}


def ink(color) -> tuple[float, ...]:
    return parse_recipe(recipe(drop(color))).at(0).ops[0]["color"]


def fault(doc) -> str:
    with pytest.raises(RecipeError) as info:
        parse_recipe(doc, "r.json")
    return str(info.value)


@pytest.mark.parametrize("name", webcolors.names())
def test_every_css3_name_is_the_colour_webcolors_gives(name):
    assert ink(name) == tuple(float(c) for c in webcolors.name_to_rgb(name))


@pytest.mark.parametrize(
    ("text", "rgb"),
    [
        ("rebeccapurple", (102, 51, 153)),  # CSS Color 4, not in the CSS3 list
        ("RebeccaPurple", (102, 51, 153)),
        ("NAVY", (0, 0, 128)),
        ("DarkSlateGrey", (47, 79, 79)),
        ("#abc", (0xAA, 0xBB, 0xCC)),
        ("#ABC", (0xAA, 0xBB, 0xCC)),
        ("#A0b1C2", (0xA0, 0xB1, 0xC2)),
        ([1, 2, 3], (1, 2, 3)),
    ],
)
def test_names_in_any_case_short_hex_and_lists(text, rgb):
    assert ink(text) == tuple(float(c) for c in rgb)


def test_names_in_the_background_tracks_and_layouts():
    track = {"keys": [{"t": 0, "v": "Black"}, {"t": 2, "v": "#fff"}]}
    rings = {"type": "rings", "center": [8, 6], "width": 1, "count": 3, "colors": ["red", "#0f0"]}
    built = parse_recipe(recipe(drop(track), rings, background="teal"))
    frame = built.at(1)
    assert frame.background == (0.0, 128.0, 128.0)
    assert frame.ops[0]["color"] == (127.5, 127.5, 127.5)  # halfway from black to white
    assert [op["color"] for op in frame.ops[1:]] == [(255, 0, 0), (0, 255, 0), (255, 0, 0)]


@pytest.mark.parametrize(
    ("doc", "path", "message"),
    [
        (recipe(drop("gren")), "ops[0].color", "unknown color 'gren' (did you mean 'green'?)"),
        (
            recipe(drop("Light Blue")),
            "ops[0].color",
            "unknown color 'Light Blue' (did you mean 'lightblue'?)",
        ),
        (
            recipe(drop("tomatoe")),
            "ops[0].color",
            "unknown color 'tomatoe' (did you mean 'tomato'?)",
        ),
        (recipe(background="whit"), "background", "unknown color 'whit' (did you mean 'white'?)"),
        (
            recipe(drop({"keys": [{"t": 0, "v": "red"}, {"t": 1, "v": "wheet"}]})),
            "ops[0].color.keys[1].v",
            "unknown color 'wheet' (did you mean 'wheat'?)",
        ),
        (
            recipe(
                {
                    "type": "line-drops",
                    "from": [0, 0],
                    "to": [9, 9],
                    "count": 2,
                    "radius": 1,
                    "colors": ["red", "bleu"],
                }
            ),
            "ops[0].colors[1]",
            "unknown color 'bleu' (did you mean 'blue'?)",
        ),  # fmt: skip
    ],
)
def test_a_near_miss_names_its_path_and_the_closest_name(doc, path, message):
    text = fault(doc)
    assert text.startswith(f"r.json: {path}: {message}"), text
    assert text.endswith(f"; expected {SHAPES}")


def test_faults_name_the_shapes():
    assert (
        fault(recipe(drop("zzz")))
        == f"r.json: ops[0].color: unknown color 'zzz'; expected {SHAPES}"
    )
    assert fault(recipe(drop("#ab"))) == (
        'r.json: ops[0].color: expected "#rrggbb" or "#rgb" (hex digits), got string \'#ab\''
    )
    assert fault(recipe(drop(7))) == (
        f"r.json: ops[0].color: expected a color ({SHAPES}) "
        'or a keyframe track {"keys": [...]}, got 7'
    )
    assert fault(recipe({**drop("red"), "center": 7})) == (
        'r.json: ops[0].center: expected a point [x, y] or a keyframe track {"keys": [...]}, got 7'
    )


def test_the_schema_completes_names_and_takes_them_in_any_case():
    color = schema()["$defs"]["color"]
    names = next(b["enum"] for b in color["anyOf"] if "enum" in b)
    assert set(names) == set(webcolors.names()) | {"rebeccapurple"}
    validator = Draft202012Validator({"$defs": schema()["$defs"], "$ref": "#/$defs/color"})
    for good in ("Gold", "rebeccapurple", "#AbC", "#aabbcc", [0, 0, 0]):
        assert validator.is_valid(good), good
    for bad in ("gren", "#abcd", "gold ", [0, 0, 256]):
        assert not validator.is_valid(bad), bad


def test_the_api_renders_named_colours():
    doc = recipe(drop("Crimson"), background="#00f")
    out = render_image(doc, size=(16, 12), device=os.environ.get("MARBLEVIDEO_TEST_DEVICE"))
    assert tuple(out[6, 8, :3]) == (220, 20, 60)
    assert tuple(out[0, 0, :3]) == (0, 0, 255)


def test_the_cli_renders_named_colours_and_refuses_a_near_miss(cli, tmp_path):
    (tmp_path / "ok.json").write_text(json.dumps(recipe(drop("gold"), background="Navy")))
    proc = cli("--ops", "ok.json", "-o", "ok.png", "-q")
    assert proc.returncode == 0, proc.stderr
    out = cv2.imread(str(tmp_path / "ok.png"))[..., ::-1]
    assert tuple(out[6, 8]) == (255, 215, 0) and tuple(out[0, 0]) == (0, 0, 128)
    (tmp_path / "r.json").write_text(json.dumps(recipe(drop("gren"))))
    proc = cli("--ops", "r.json", "-o", "bad.png")
    assert proc.returncode == 2
    assert one_line(proc) == (
        "marblevideo: r.json: ops[0].color: unknown color 'gren' (did you mean 'green'?); "
        f"expected {SHAPES}"
    )
    assert not (tmp_path / "bad.png").exists()
