"""Recipe fuzzing: whatever JSON a user hands us, the loader either
accepts it, and then the renderer draws a frame from it, or refuses it with one
RecipeError naming the file and the JSON path. Never another exception, never a hang.

Hypothesis runs derandomized (a fixed seed, no example database), so CI sees
the same examples on every run: 1000 arbitrary JSON documents, 1200 mutations
of valid recipes and 300 valid ones scaled to extremes (parsed in-process, the
valid ones rendered at 16x12 on the session renderer), 300 more through files,
and two dozen through the real command line.
"""

from __future__ import annotations

import copy
import json
import math
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest
from helpers import subprocess_env
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from recipes import random_recipe

from marblevideo.errors import RecipeError
from marblevideo.marbler import Marbler
from marblevideo.ops import REGISTRY
from marblevideo.recipe import load_recipe, parse_recipe

pytestmark = pytest.mark.tier("integration")

SOURCE = "fuzz.json"
#: A JSON path as messages write it: ops[3].center.keys[1].t, ["odd key"], or empty.
PATH = re.compile(
    r'^(|([A-Za-z0-9_$]+|\["(?:[^"\\]|\\.)*"\])(\.[A-Za-z0-9_$]+|\[\d+\]|\["(?:[^"\\]|\\.)*"\])*)$'
)

FUZZ = settings(
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

# ---------------------------------------------------------------------------- strategies

numbers = st.one_of(
    st.integers(min_value=-(10**40), max_value=10**40),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, -0.0, 1e-300, 5e-324, 1e30, 1e31, -1e30, 2**63, 1e308, 256, -1]),
)
scalars = st.one_of(st.none(), st.booleans(), numbers, st.text(max_size=12))
json_values = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=5), st.dictionaries(st.text(max_size=8), inner, max_size=5)
    ),
    max_leaves=30,
)

#: Field names a mutation may rename to: typos, other ops' fields, odd keys.
NAMES = st.one_of(
    st.sampled_from(
        ["centre", "Center", "radius ", "lamda", "alpha", "keys", "t", "v", "ease", "type", ""]
    ),
    st.text(max_size=6),
)
#: Replacement values: off-range, wrong type, huge, non-finite, nested.
BAD_VALUES = st.one_of(
    numbers,
    st.sampled_from(
        [
            "#12345",
            "#gggggg",
            [1, 2],
            [1, 2, 3, 4],
            [256, 0, 0],
            {"keys": []},
            {"keys": [{"t": 1, "v": 2}, {"t": 1, "v": 3}]},
            {"keys": [{"t": 0, "v": 1, "ease": [2, 0, 0, 1]}]},
            "ease-in-out",
            "rgss",
            "mirror",
            "vortex",
        ]
    ),
    json_values,
)

BASES = [random_recipe(seed) for seed in (0, 7, 13)]


def _nodes(doc, path=()):
    """Every (path, value) in a document, the root included."""
    yield path, doc
    if isinstance(doc, dict):
        for key, value in doc.items():
            yield from _nodes(value, (*path, key))
    elif isinstance(doc, list):
        for index, value in enumerate(doc):
            yield from _nodes(value, (*path, index))


def _nest(value, depth):
    for _ in range(depth):
        value = [value]
    return value


@st.composite
def mutated_recipes(draw):
    """A valid recipe with one to three faults: a field dropped, renamed or retyped, a
    number pushed out of range or made huge/non-finite, a value wrapped in lists or
    objects (deep nesting), an op type or enum swapped."""
    doc = copy.deepcopy(draw(st.sampled_from(BASES)))
    for _ in range(draw(st.integers(1, 3))):
        nodes = list(_nodes(doc))
        path, value = draw(st.sampled_from(nodes))
        kind = draw(st.sampled_from(["drop", "rename", "replace", "scale", "nest", "deep", "add"]))
        if not path:
            kind = draw(st.sampled_from(["add", "drop"])) if isinstance(doc, dict) else "replace"
        parent = doc
        for step in path[:-1]:
            parent = parent[step]
        last = path[-1] if path else None
        if kind == "drop" and path:
            del parent[last]
        elif kind == "drop":
            doc.pop(draw(st.sampled_from(sorted(doc))), None) if doc else None
        elif kind == "rename" and isinstance(parent, dict):
            parent[draw(NAMES)] = parent.pop(last)
        elif kind == "scale" and isinstance(value, (int, float)) and not isinstance(value, bool):
            factor = draw(st.sampled_from([-1, 0, 1e-40, 1e6, 1e29, 1e31, 1e300, math.inf]))
            parent[last] = value * factor
        elif kind == "nest" and path:
            parent[last] = draw(st.sampled_from([[value], {"keys": value}, {"v": value}]))
        elif kind == "deep" and path:
            parent[last] = _nest(value, draw(st.integers(10, 300)))
        elif kind == "add" and isinstance(value, dict):
            value[draw(NAMES)] = copy.deepcopy(draw(BAD_VALUES))
        elif path:
            parent[last] = copy.deepcopy(draw(BAD_VALUES))
        else:
            doc = copy.deepcopy(draw(BAD_VALUES))
        if not isinstance(doc, (dict, list)):
            break
    return doc


@st.composite
def scaled_recipes(draw):
    """A valid recipe whose numbers are scaled to extremes that stay valid: every
    number but colors, eases, times (``heal`` and a stroke's too), counts and shares
    multiplied by a positive factor from 1e-12 to 1e24 (signs kept). Ops whose own
    check bounds their parameters together or against defaults (jiggle's
    |2 pi major / wavelength| < 1, rake's, a stroke's steps) keep their values."""
    doc = copy.deepcopy(draw(st.sampled_from(BASES)))
    factors = st.sampled_from([1e-12, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e12, 1e24])
    fixed = {"color", "ease", "t", "start", "end", "heal", "times"}
    for index, op in enumerate(doc["ops"]):
        definition = REGISTRY[op["type"]]
        # counts and bounded shares (a stroke's drag in -4..4) are no sizes to scale
        counts = {p.name for p in definition.params if p.kind == "count" or p.slider == "share"}
        if definition.check:
            continue
        for path, value in list(_nodes(op)):
            if not path or set(path) & (fixed | counts):
                continue
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                parent = doc["ops"][index]
                for step in path[:-1]:
                    parent = parent[step]
                parent[path[-1]] = value * draw(factors)
    return doc


# ---------------------------------------------------------------------------- checks


def check_refusal(exc: RecipeError, source: str = SOURCE) -> None:
    """One line, starting with the file name, naming a well-formed JSON path."""
    text = str(exc)
    assert "\n" not in text
    assert text.startswith(f"{source}: "), text
    assert PATH.match(exc.path), (exc.path, text)
    if exc.path:
        assert text.startswith(f"{source}: {exc.path}: "), text
    assert exc.message and exc.exit_code == 2


def parse_or_refuse(doc):
    try:
        return parse_recipe(doc, SOURCE)
    except RecipeError as exc:
        check_refusal(exc)
        return None


def render_tiny(renderer, recipe) -> None:
    """A 16x12 frame at the end and halfway: uint8 RGBA, same pixels twice."""
    marbler = Marbler(recipe, renderer)
    image = None
    if recipe.canvas is None:  # the recipe takes its canvas from the input
        image = np.full((12, 16, 3), 90, np.uint8)
    end = recipe.end_time()
    for t in (end, end / 2):
        out = marbler.render(image, t, (16, 12))
        assert out.shape == (12, 16, 4) and out.dtype == np.uint8
        assert np.array_equal(out, marbler.render(image, t, (16, 12)))


# ---------------------------------------------------------------------------- tests


@settings(FUZZ, max_examples=1000)
@given(json_values)
def test_arbitrary_json_parses_or_is_refused_with_a_path(doc):
    parse_or_refuse(doc)


@settings(FUZZ, max_examples=1200)
@given(mutated_recipes())
def test_mutated_recipes_render_or_are_refused_with_a_path(renderer, doc):
    recipe = parse_or_refuse(doc)
    if recipe is not None:
        render_tiny(renderer, recipe)


@settings(FUZZ, max_examples=300)
@given(scaled_recipes())
def test_extreme_valid_values_render(renderer, doc):
    """Huge and tiny (but valid) values parse and render without a crash or a numeric
    warning (float32 overflow), the same pixels twice."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        render_tiny(renderer, parse_recipe(doc, SOURCE))


@settings(FUZZ, max_examples=200)
@given(mutated_recipes())
def test_the_same_mutations_from_a_file(tmp_path_factory, doc):
    """Through json text and load_recipe: the file name leads every message."""
    path = tmp_path_factory.getbasetemp() / "fuzz.json"
    path.write_text(json.dumps(doc))  # NaN and Infinity are written as JSON literals
    try:
        load_recipe(path)
    except RecipeError as exc:
        check_refusal(exc, str(path))


@settings(FUZZ, max_examples=100)
@given(st.binary(max_size=64) | st.text(max_size=40).map(str.encode))
def test_arbitrary_bytes_are_refused_with_line_and_column(tmp_path_factory, data):
    path = tmp_path_factory.getbasetemp() / "bytes.json"
    path.write_bytes(data)
    try:
        load_recipe(path)
    except RecipeError as exc:
        check_refusal(exc, str(path))
    except ValueError as exc:  # UsageError: not UTF-8
        assert "cannot read recipe" in str(exc) and "\n" not in str(exc)


def test_deeply_nested_json_is_refused_not_a_recursion_error(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text('{"ops": ' + "[" * 100_000 + "]" * 100_000 + "}")
    with pytest.raises(RecipeError) as info:
        load_recipe(path)
    check_refusal(info.value, str(path))


# ---------------------------------------------------------------------------- the real CLI


@settings(FUZZ, max_examples=24)
@given(mutated_recipes())
def test_mutations_through_the_command_line(tmp_path_factory, doc):
    """Exit 0 with a picture, or exit 2 with one line naming the file; never a traceback."""
    folder = tmp_path_factory.mktemp("cli")
    (folder / "r.json").write_text(json.dumps(doc))

    proc = subprocess.run(
        [sys.executable, "-m", "marblevideo", "--ops", "r.json", "-o", "o.png", "--size", "16x12"],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=120,
        env=subprocess_env(),
    )
    assert "Traceback" not in proc.stderr
    left = sorted(p.name for p in folder.iterdir())
    if proc.returncode == 0:
        assert left == ["o.png", "r.json"]
    else:
        assert proc.returncode == 2, proc.stderr
        lines = proc.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("marblevideo: r.json: "), proc.stderr
        assert left == ["r.json"]
