"""``marblevideo ops``: every op type and drop layout of the registry
with its parameters' kinds, defaults and help, wrapped to the terminal;
``ops TYPE`` in full; an unknown type is one line with a did-you-mean."""

from __future__ import annotations

import json

import pytest
from helpers import one_line

from marblevideo import parse_recipe
from marblevideo.cli.catalog import KIND_LABELS
from marblevideo.ops import KINDS, LAYOUTS, REGISTRY, recipe_types, type_def

pytestmark = pytest.mark.tier("fast")


def squashed(text: str) -> str:
    return " ".join(text.split())


def test_every_kind_has_a_label():
    assert set(KIND_LABELS) == set(KINDS)


def test_ops_lists_every_type_with_its_parameters(cli):
    proc = cli("ops")
    assert proc.returncode == 0, proc.stderr
    flat = squashed(proc.stdout)
    for type_ in recipe_types():
        definition = type_def(type_)
        assert f"  {type_}: " in proc.stdout, type_
        assert squashed(definition.help) in flat, type_
        for p in definition.params:
            row = f"{p.name} {KIND_LABELS[p.kind]} "
            assert row in flat, (type_, p.name)
            assert squashed(p.help) in flat
    assert "angle number = 0 Rotation of the layout" in flat  # a default
    assert 'distribution uniform|normal = "uniform"' in flat
    assert flat.index("ops:") < flat.index("drop layouts") < flat.index("rings:")


@pytest.mark.parametrize("columns", [60, 100])
def test_the_listing_fits_the_terminal(cli, columns, monkeypatch):
    monkeypatch.setenv("COLUMNS", str(columns))
    proc = cli("ops")
    lines = proc.stdout.splitlines()
    assert max(map(len, lines)) <= columns
    assert max(map(len, lines)) > columns - 10  # and uses it


@pytest.mark.parametrize("type_", ["rake", "drop", "scatter-drops"])
def test_ops_type_shows_one_in_full(cli, type_):
    proc = cli("ops", type_)
    assert proc.returncode == 0, proc.stderr
    definition = type_def(type_)
    flat = squashed(proc.stdout)
    assert flat.startswith(f"{type_}: {squashed(definition.help)}")
    for p in definition.params:
        assert f"{p.name} {KIND_LABELS[p.kind]}" in flat
        keyed = f"{squashed(p.help)} May be a keyframe track."
        assert (keyed in flat) == p.tracked, p.name
    assert "start seconds optional" in flat and "end seconds optional" in flat
    assert "hidden true/false false marblevideo: true keeps the op in the file" in flat
    example = proc.stdout.split("Example (JSON):\n", 1)[1].strip()
    assert json.loads(example) == definition.example
    parse_recipe({"canvas": [80, 60], "ops": [json.loads(example)]})  # a valid op as printed
    if type_ in LAYOUTS:
        assert "A drop layout" in proc.stdout
    else:
        laws = {"rake": "alpha * p", "drop": "radius * sqrt(p)"}
        assert f"Progress p (0 -> 1 from start to end): {laws[type_]}." in proc.stdout
        assert ("Ink:" in proc.stdout) == REGISTRY[type_].ink


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["ops", "vortx"], "ops: unknown op type 'vortx' (did you mean 'vortex'?); see "),
        (["ops", "grid-drop"], "ops: unknown op type 'grid-drop' (did you mean 'grid-drops'?)"),
        (["ops", "zzz"], "ops: unknown op type 'zzz'; see marblevideo ops"),
        (["ops", "drop", "comb"], "unrecognized arguments: comb"),
    ],
)
def test_mistakes_are_one_line_and_exit_2(cli, argv, says):
    proc = cli(*argv)
    assert proc.returncode == 2
    assert says in one_line(proc)
