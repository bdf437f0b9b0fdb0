"""Signals in recipes (revision 3): parsing, validation messages with JSON paths,
evaluation through a SignalValues source, and what they make of a recipe's time."""

from __future__ import annotations

import copy

import jsonschema
import pytest

from marblevideo.errors import RecipeError
from marblevideo.ops import type_def
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.schema import schema
from marblevideo.recipe.signals import Signal, SignalTrack, name_fault

pytestmark = pytest.mark.tier("fast")

DROP = {"type": "drop", "center": [50, 40], "radius": 10, "color": "red"}
VORTEX = {"type": "vortex", "center": [50, 40], "alpha": 100, "lambda": 20}
LOW = {"signal": "audio.low", "range": [5, 20]}


def recipe_with(*ops: dict, **top) -> dict:
    return {"canvas": [100, 80], "ops": [copy.deepcopy(op) for op in ops], **top}


def fault(data: object) -> str:
    with pytest.raises(RecipeError) as info:
        parse_recipe(data, "pulse.json")
    return str(info.value)


def signal_fault(signal: dict, op: dict = DROP, field: str = "radius") -> str:
    return fault(recipe_with(DROP, {**op, field: signal}))


class Ramp:
    """A source whose every signal is t / 10 (clamped), recording what it was asked."""

    def __init__(self):
        self.asked: list[tuple[Signal, float]] = []

    def at(self, signal: Signal, t: float) -> float:
        self.asked.append((signal, t))
        return min(max(t / 10.0, 0.0), 1.0)


# ---------------------------------------------------------------- names


@pytest.mark.parametrize(
    "name",
    [
        "audio.level",
        "audio.low",
        "audio.mid",
        "audio.high",
        "osc:/fader/1",
        "osc:/x",
        "midi:cc:1:0",
        "midi:cc:16:127",
        "midi:note:10:60",
    ],
)
def test_every_name_the_contract_defines_parses(name):
    assert name_fault(name) is None
    parse_recipe(recipe_with({**DROP, "radius": {"signal": name, "range": [1, 2]}}))


def test_names_say_their_source_and_parts():
    assert Signal("audio.high").source == "audio" and Signal("audio.high").band == "high"
    assert Signal("osc:/a/b").source == "osc" and Signal("osc:/a/b").osc_address == "/a/b"
    assert Signal("midi:note:3:64").midi == ("note", 3, 64)
    assert Signal("midi:cc:1:7").controller and not Signal("audio.low").controller


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("audio.bass", "unknown signal 'audio.bass'"),
        ("audio.lows", "(did you mean 'audio.low'?)"),
        ("osc:/", "expected an OSC address"),
        ("osc:fader", "expected an OSC address"),
        ("osc:/a b", "expected an OSC address"),
        ("osc:/a*", "expected an OSC address"),
        ("midi:cc:0:7", "MIDI channel must be 1..16, got 0"),
        ("midi:cc:17:7", "MIDI channel must be 1..16, got 17"),
        ("midi:note:1:128", "must be 0..127, got 128"),
        ("midi:pc:1:2", "expected midi:cc:CH:N or midi:note:CH:N"),
        ("midi:cc:1", "expected midi:cc:CH:N or midi:note:CH:N"),
    ],
)
def test_bad_names_are_refused_at_their_path(name, expected):
    message = signal_fault({"signal": name, "range": [1, 2]})
    assert message.startswith("pulse.json: ops[1].radius.signal: ")
    assert expected in message


# ---------------------------------------------------------------- validation


@pytest.mark.parametrize(
    ("signal", "path", "expected"),
    [
        ({"signal": "audio.low"}, "ops[1].radius", "missing required field 'range'"),
        ({**LOW, "range": [5]}, "ops[1].radius.range", "expected a range [lo, hi]"),
        ({**LOW, "range": [1, 2, 3]}, "ops[1].radius.range", "expected a range [lo, hi]"),
        ({**LOW, "range": [-5, 20]}, "ops[1].radius.range[0]", "must be > 0, got -5"),
        ({**LOW, "range": [5, "x"]}, "ops[1].radius.range[1]", "expected a number"),
        ({**LOW, "db": [0, -10]}, "ops[1].radius.db", "d0 < d1, got [0, -10]"),
        ({**LOW, "db": [-20, -20]}, "ops[1].radius.db", "d0 < d1, got [-20, -20]"),
        ({**LOW, "attack": -0.1}, "ops[1].radius.attack", "must be >= 0, got -0.1"),
        ({**LOW, "release": -1}, "ops[1].radius.release", "must be >= 0, got -1"),
        ({**LOW, "initial": 0.5}, "ops[1].radius.initial", "controller signal's option"),
        (
            {"signal": "osc:/x", "range": [1, 2], "db": [-9, 0]},
            "ops[1].radius.db",
            "an audio signal's option",
        ),
        (
            {"signal": "osc:/x", "range": [1, 2], "initial": 2},
            "ops[1].radius.initial",
            "must be <= 1, got 2",
        ),
        ({**LOW, "gain": 2}, "ops[1].radius", "unknown field 'gain'"),
        ({**LOW, "signal": 3}, "ops[1].radius.signal", "expected a string, got 3"),
    ],
)
def test_bad_signals_are_refused_with_their_json_path(signal, path, expected):
    message = signal_fault(signal)
    assert message.startswith(f"pulse.json: {path}: "), message
    assert expected in message


@pytest.mark.parametrize(
    ("op", "field", "path"),
    [
        (DROP, "center", "ops[1].center"),
        (DROP, "color", "ops[1].color"),
        ({"type": "rings", "center": [50, 40], "width": 5, "count": 3}, "width", "ops[1].width"),
        (
            {"type": "scatter-drops", "center": [50, 40], "size": [20, 20], "count": 3},
            "angle",
            "ops[1].angle",
        ),
    ],
)
def test_a_signal_where_none_is_taken_is_refused(op, field, path):
    message = signal_fault(LOW, op, field)
    assert message == f"pulse.json: {path}: " + (
        "takes no signal: only keyable numbers follow signals (points, colors, layout fields "
        "and constants take none)"
    )


def test_the_background_takes_no_signal():
    assert fault(recipe_with(DROP, background=LOW)).startswith("pulse.json: background: takes no")


def test_the_schema_takes_signals_on_numbers_only():
    check = jsonschema.Draft202012Validator(schema())
    assert check.is_valid(recipe_with({**VORTEX, "alpha": {**LOW, "range": [-50, 50]}}))
    assert not check.is_valid(recipe_with({**DROP, "center": LOW}))
    assert not check.is_valid(recipe_with({**DROP, "radius": {**LOW, "range": [0, 2]}}))


def test_every_keyable_number_of_every_op_takes_a_signal():
    for entry in schema()["$defs"]["op"]["allOf"]:
        definition = type_def(entry["if"]["properties"]["type"]["const"])
        for param in definition.params:
            ref = schema()["$defs"][definition.type]["properties"][param.name]["$ref"]
            branches = schema()["$defs"].get(ref.rsplit("/", 1)[1], {}).get("anyOf", [])
            takes = any(b["$ref"].endswith("Signal") for b in branches)
            wanted = param.tracked and param.kind in ("number", "positive", "nonnegative")
            assert takes == wanted, (definition.type, param.name)


# ---------------------------------------------------------------- evaluation


def test_a_signal_maps_y_onto_the_range_through_the_source():
    recipe = parse_recipe(recipe_with({**VORTEX, "alpha": {**LOW, "range": [-50, 150]}}))
    ramp = Ramp()
    bound = recipe.bind(ramp)
    assert bound.at(0.0).ops[0]["alpha"] == -50
    assert bound.at(5.0).ops[0]["alpha"] == pytest.approx(50)
    assert bound.at(10.0).ops[0]["alpha"] == pytest.approx(150)
    assert ramp.asked[-1] == (Signal("audio.low"), 10.0)
    assert bound == recipe  # the source is no part of the design


def test_options_reach_the_source():
    value = {"signal": "audio.mid", "range": [1, 2], "db": [-40, -6], "attack": 0.1, "release": 1}
    recipe = parse_recipe(recipe_with({**DROP, "radius": value})).bind(Ramp())
    recipe.at(1.0)
    (signal, _), *_ = recipe.signals.asked
    assert signal == Signal("audio.mid", db=(-40.0, -6.0), attack=0.1, release=1.0)
    assert recipe.ops[0].params["radius"].json() == value


def test_progress_laws_apply_to_a_signal_value():
    op = {**DROP, "radius": {**LOW, "range": [4, 4]}, "start": 0, "end": 4}
    state = parse_recipe(recipe_with(op)).bind(Ramp()).at(1.0).ops[0]
    assert state["radius"] == pytest.approx(4 * 0.5)  # radius * sqrt(p), p = 1/4


def test_without_a_source_a_signal_rests():
    audio = parse_recipe(recipe_with({**DROP, "radius": LOW}))
    assert audio.at(3.0).ops[0]["radius"] == 5
    osc = {"signal": "osc:/r", "range": [10, 20], "initial": 0.25}
    assert parse_recipe(recipe_with({**DROP, "radius": osc})).at(3.0).ops[0]["radius"] == 12.5


def test_a_recipe_with_a_signal_is_animated_but_adds_no_end_time():
    still = parse_recipe(recipe_with(DROP))
    assert not still.is_animated
    recipe = parse_recipe(recipe_with(DROP, {**VORTEX, "alpha": {**LOW, "range": [0, 90]}}))
    assert recipe.is_animated and recipe.end_time() == 0.0
    ((path, track),) = recipe.signal_uses()
    assert path == "ops[1].alpha" and isinstance(track, SignalTrack) and track.varies


def test_signal_uses_name_the_file_entries_of_hidden_and_layout_recipes():
    rings = {"type": "rings", "center": [50, 40], "width": 5, "count": 3, "colors": ["red"]}
    hidden = {**VORTEX, "hidden": True, "alpha": {**LOW, "range": [0, 1]}}
    shown = {**VORTEX, "lambda": {"signal": "midi:cc:1:7", "range": [5, 50]}}
    recipe = parse_recipe(recipe_with(rings, hidden, shown))
    assert [path for path, _ in recipe.signal_uses()] == ["ops[2].lambda"]


def test_an_ops_own_rule_holds_at_both_ends_of_a_range():
    jiggle = dict(type_def("jiggle").example)
    wavelength = jiggle["wavelength"]
    fine = {"signal": "audio.low", "range": [0, wavelength / 10]}
    parse_recipe(recipe_with({**jiggle, "major": fine}))
    too_far = {"signal": "audio.low", "range": [0, wavelength / 5]}  # 2 pi / 5 > 1
    message = fault(recipe_with({**jiggle, "major": too_far}))
    assert message.startswith("pulse.json: ops[0].major.range[1]: |2 pi major / wavelength|")
    low_end = {"signal": "osc:/w", "range": [wavelength, 2]}  # at y = 1 the wavelength is 2
    message = fault(recipe_with({**jiggle, "major": 1, "wavelength": low_end}))
    assert message.startswith("pulse.json: ops[0].major: |2 pi major / wavelength|")  # its choice
    assert "got 3.14 at t=0" in message


def test_sources_ask_the_source_of_each_signals_kind():
    from marblevideo.signals import Sources

    class Held:
        def __init__(self, y):
            self.y = y

        def at(self, signal, t):
            return self.y

    both = Sources(audio=Ramp(), osc=Held(0.25))
    recipe = recipe_with(
        {**VORTEX, "alpha": {**LOW, "range": [0, 100]}},
        {**VORTEX, "lambda": {"signal": "osc:/l", "range": [10, 50]}},
    )
    frame = parse_recipe(recipe).bind(both).at(5.0)
    assert frame.ops[0]["alpha"] == pytest.approx(50) and frame.ops[1]["lambda"] == 20
