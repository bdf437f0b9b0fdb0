"""The tests' own shape: conftest.py holds fixtures only and no module imports it;
renderers are made by one helper (on the test device); subprocesses get the
checkout's PYTHONPATH from one helper; random recipes cover every registered op
type (a new op is covered by adding its definition, or named here)."""

from __future__ import annotations

import ast
import re
from dataclasses import replace

import pytest
from helpers import ROOT
from recipes import GENERATORS, NOT_RANDOM, OPS, random_recipe

from marblevideo.ops import REGISTRY
from marblevideo.recipe import parse_recipe

TESTS = ROOT / "tests"
#: The folders whose modules may be tempted to import the tests' conftest.
SOURCES = sorted(
    p
    for folder in ("tests", "benchmarks", "scripts", "samples")
    for p in (ROOT / folder).rglob("*.py")
)
IDS = [str(p.relative_to(ROOT)) for p in SOURCES]


def tree(path) -> ast.Module:
    return ast.parse(path.read_text(), str(path))


@pytest.mark.parametrize("path", SOURCES, ids=IDS)
def test_nothing_imports_conftest(path):
    """Helpers live in modules (helpers.py, recipes.py...): pytest loads conftest.py
    itself, and a second import of it runs it twice under another name."""
    found = re.findall(
        r"^\s*(?:from\s+(?:tests\.)?conftest\s+import|import\s+(?:tests\.)?conftest)\b",
        path.read_text(),
        re.M,
    )
    assert not found, found


def test_conftest_defines_fixtures_and_hooks_only():
    names = []
    for node in tree(TESTS / "conftest.py").body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            fixture = any("fixture" in ast.unparse(d) for d in node.decorator_list)
            if not fixture and not node.name.startswith("pytest_"):
                names.append(node.name)
    assert not names, f"helpers belong in tests/helpers.py: {names}"


def calls(path, name: str):
    for node in ast.walk(tree(path)):
        if isinstance(node, ast.Call):
            func = node.func
            called = func.id if isinstance(func, ast.Name) else getattr(func, "attr", None)
            if called == name:
                yield node


@pytest.mark.parametrize("path", sorted(TESTS.glob("*.py")), ids=lambda p: p.name)
def test_renderers_are_made_by_fresh_renderer(path):
    """Tests take the session's ``renderer`` fixture, or ``fresh_renderer()`` where
    they need a renderer of their own: both run on MARBLEVIDEO_TEST_DEVICE
    (code in strings, run in a subprocess, is not looked at)."""
    if path.name == "helpers.py":
        return
    made = [node.lineno for node in calls(path, "Renderer")]
    assert not made, f"{path.name}: Renderer(...) on lines {made}: use helpers.fresh_renderer"


@pytest.mark.parametrize("path", sorted(TESTS.glob("*.py")), ids=lambda p: p.name)
def test_subprocesses_take_pythonpath_from_the_helper(path):
    """PYTHONPATH is set only to helpers.pythonpath() (the checkout, then the
    caller's), never to the checkout alone."""
    if path.name == "helpers.py":
        return
    bad = []
    for node in ast.walk(tree(path)):
        pairs = []
        if isinstance(node, ast.Dict):
            pairs = [
                (k.value, v)
                for k, v in zip(node.keys, node.values, strict=True)
                if isinstance(k, ast.Constant)
            ]
        elif isinstance(node, ast.keyword):
            pairs = [(node.arg, node.value)]
        for key, value in pairs:
            if key == "PYTHONPATH" and ast.unparse(value) != "pythonpath()":
                bad.append(node.lineno if hasattr(node, "lineno") else value.lineno)
    assert not bad, (
        f"{path.name}: PYTHONPATH set by hand on lines {bad}: use helpers.subprocess_env"
    )


def uncovered(registry, generators, excluded) -> list[str]:
    """Registered op types with neither a random generator nor a reason to have none."""
    return [t for t in registry if t not in generators and t not in excluded]


def test_random_recipes_cover_every_registered_type():
    """A new op is random-generated once listed in recipes.GENERATORS (or left out,
    with the reason, in recipes.NOT_RANDOM); nothing listed is unregistered."""
    missing = uncovered(REGISTRY, GENERATORS, NOT_RANDOM)
    assert not missing, f"no random generator in tests/recipes.py GENERATORS: {missing}"
    assert set(GENERATORS).isdisjoint(NOT_RANDOM)
    assert set(GENERATORS) | set(NOT_RANDOM) <= set(REGISTRY)
    assert all(reason.strip() for reason in NOT_RANDOM.values())
    assert tuple(t for t in REGISTRY if t not in NOT_RANDOM) == OPS


def test_a_new_op_type_is_named_until_it_has_a_generator():
    whirl = replace(REGISTRY["vortex"], type="whirl")
    registry = {**REGISTRY, "whirl": whirl, "swirl": replace(whirl, type="swirl")}
    assert uncovered(registry, GENERATORS, NOT_RANDOM) == ["whirl", "swirl"]
    assert uncovered(registry, {**GENERATORS, "whirl": None}, {**NOT_RANDOM, "swirl": "why"}) == []


@pytest.mark.parametrize("seed", range(3))
def test_a_recipe_of_as_many_ops_as_types_holds_every_type(seed):
    recipe = random_recipe(seed, n_ops=len(OPS))
    assert sorted(op["type"] for op in recipe["ops"]) == sorted(OPS)
    parse_recipe(recipe, "random.json")
