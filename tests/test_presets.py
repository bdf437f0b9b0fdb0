"""Presets: the bundled recipes by name, wherever a recipe is taken
(``--ops NAME``, the API, ``live``) unless a file of that name exists; ``marblevideo
presets`` lists them and prints one; and the optional top-level ``description``,
which the renderer ignores."""

from __future__ import annotations

import json
import os
import re

import cv2
import numpy as np
import pytest
from helpers import ROOT, one_line

from marblevideo import RecipeError, UsageError, load_recipe, parse_recipe, render_image
from marblevideo.bundled import presets
from marblevideo.marbler import as_recipe

pytestmark = pytest.mark.tier("fast")

SAMPLES = ROOT / "samples"

DESIGN = {"canvas": [16, 12], "ops": [{"type": "drop", "center": [8, 6], "radius": 4,
                                       "color": "#123456"}]}  # fmt: skip


def test_a_description_is_kept_and_changes_no_frame():
    described = parse_recipe({**DESIGN, "description": "One blue drop."})
    assert described.description == "One blue drop."
    assert parse_recipe(DESIGN).description == ""
    assert described.at(0) == parse_recipe(DESIGN).at(0)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("x" * 201, "too long: at most 200 characters, got 201"),
        (["a"], "expected a string, got a list of 1"),
    ],
)
def test_a_bad_description_is_one_line_with_its_path(value, message):
    with pytest.raises(RecipeError) as info:
        parse_recipe({**DESIGN, "description": value}, "r.json")
    assert str(info.value) == f"r.json: description: {message}"


# ---------------------------------------------------------------------------- the presets

SAMPLE_RECIPES = sorted(p.stem for p in SAMPLES.glob("*.json") if p.name != "recipe.schema.json")


def test_every_sample_recipe_is_a_preset_with_a_one_line_description():
    assert list(presets()) == SAMPLE_RECIPES
    for name, path in presets().items():
        assert path == SAMPLES / f"{name}.json"
        text = json.loads(path.read_text())["description"]
        assert text == load_recipe(path).description
        assert 0 < len(text) <= 120 and "\n" not in text, name


def test_every_preset_ships_in_the_wheel():
    tomllib = pytest.importorskip("tomllib")
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    shipped = config["tool"]["hatch"]["build"]["targets"]["wheel"]["force-include"]
    for name in presets():
        assert shipped[f"samples/{name}.json"] == f"marblevideo/samples/{name}.json"


def test_the_api_takes_a_preset_wherever_it_takes_a_recipe(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no file named so here
    assert load_recipe("swirl").source == str(SAMPLES / "swirl.json")
    assert load_recipe("swirl.json").ops == load_recipe(SAMPLES / "swirl.json").ops
    assert as_recipe("tile").edges == "repeat"
    device = os.environ.get("MARBLEVIDEO_TEST_DEVICE")
    by_name = render_image("figure6", size=(40, 40), device=device)
    by_file = render_image(SAMPLES / "figure6.json", size=(40, 40), device=device)
    assert np.array_equal(by_name, by_file)
    with pytest.raises(UsageError) as info:
        load_recipe("swirll")
    assert str(info.value) == (
        "cannot read recipe swirll: No such file or directory, nor a preset of that name "
        "(did you mean 'swirl'?); `marblevideo presets` lists them"
    )


def test_a_file_always_wins_over_a_preset(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "swirl").write_text(json.dumps(DESIGN))
    (tmp_path / "tile.json").write_text(json.dumps({**DESIGN, "description": "mine"}))
    assert load_recipe("swirl").source == "swirl"
    assert load_recipe("swirl").ops == parse_recipe(DESIGN).ops
    assert load_recipe("tile.json").description == "mine"
    assert load_recipe("tile").source == str(SAMPLES / "tile.json")  # no file "tile"


def test_a_path_with_a_folder_is_never_a_preset(tmp_path):
    """Not read as one; the message names the preset of its file's name (the
    README's ``--ops samples/swirl.json`` run outside the checkout)."""
    with pytest.raises(UsageError) as info:
        load_recipe(tmp_path / "swirl.json")
    assert str(info.value) == (
        f"cannot read recipe {tmp_path / 'swirl.json'}: No such file or directory; a preset "
        "has that name: --ops swirl (`marblevideo presets` lists them)"
    )
    with pytest.raises(UsageError) as info:
        load_recipe(tmp_path / "mine.json")
    assert (
        str(info.value) == f"cannot read recipe {tmp_path / 'mine.json'}: No such file or directory"
    )


# ---------------------------------------------------------------------------- the command line


def test_presets_lists_each_name_and_description(cli):
    proc = cli("presets")
    assert proc.returncode == 0, proc.stderr
    text = " ".join(proc.stdout.split())  # descriptions wrap to the terminal
    for name, path in presets().items():
        assert re.search(rf"^{re.escape(name)}  ", proc.stdout, re.M), name
        assert load_recipe(path).description in text
    assert str(SAMPLES) not in proc.stdout
    with_paths = cli("presets", "--paths")
    assert all(str(path) in with_paths.stdout for path in presets().values())


def test_presets_name_prints_the_recipe_to_copy_and_edit(cli, tmp_path):
    proc = cli("presets", "swirl")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == (SAMPLES / "swirl.json").read_text()
    assert cli("presets", "swirl.json").stdout == proc.stdout
    assert cli("presets", "swirl", "--paths").stdout == f"{SAMPLES / 'swirl.json'}\n"
    (tmp_path / "my.json").write_text(proc.stdout.replace('"mirror"', '"repeat"'))
    assert load_recipe(tmp_path / "my.json").edges == "repeat"


def test_an_unknown_preset_is_one_line_with_the_close_names(cli):
    proc = cli("presets", "chevrn")
    assert proc.returncode == 2
    assert one_line(proc) == (
        "marblevideo: presets: no preset 'chevrn' (did you mean 'chevron'?); there are "
        + ", ".join(presets())
    )


def test_ops_name_renders_the_preset_unless_a_file_has_that_name(cli, tmp_path):
    size = ("--size", "48x32", "-q")
    assert cli("--ops", "bouquet", "-o", "a.png", *size).returncode == 0
    assert cli("--ops", SAMPLES / "bouquet.json", "-o", "b.png", *size).returncode == 0
    a, b = (cv2.imread(str(tmp_path / n)) for n in ("a.png", "b.png"))
    assert np.array_equal(a, b) and a.std() > 10
    (tmp_path / "bouquet").write_text(json.dumps({**DESIGN, "background": "#00ff00"}))
    assert cli("--ops", "bouquet", "-o", "c.png", *size).returncode == 0
    c = cv2.imread(str(tmp_path / "c.png"))
    assert tuple(c[0, 0]) == (0, 255, 0)  # the file's green sheet (BGR)


def test_ops_name_with_no_file_and_no_preset_is_one_line(cli, tmp_path):
    proc = cli("--ops", "bouqet", "-o", "x.png")
    assert proc.returncode == 2
    assert one_line(proc) == (
        "marblevideo: cannot read recipe bouqet: No such file or directory, nor a preset of "
        "that name (did you mean 'bouquet'?); `marblevideo presets` lists them"
    )
    assert not (tmp_path / "x.png").exists()


def test_live_takes_a_preset(cli, tmp_path):
    proc = cli(
        "live", "test", "--size", "64x48", "--fps", "10", "--ops", "swirl",
        "--duration", "1", "-o", "take.mp4",
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "take.mp4").stat().st_size > 0
