"""The tests' own shape: every test module declares its tier; tests/ holds test
modules and conftest.py, what they import lives in tests/support/; conftest.py
holds fixtures and hooks only and no module imports it; renderers are made by one
helper (on the test device); subprocesses get the checkout's PYTHONPATH from one
helper; random recipes cover every registered op type (a new op is covered by
adding its definition, or named here)."""

from __future__ import annotations

import ast
import re
from dataclasses import replace

import numpy as np
import pytest
import tomllib
from helpers import ROOT, TIERS
from recipes import (
    GENERATORS,
    NOT_RANDOM,
    OPS,
    generator,
    random_recipe,
    random_types,
    valid_registry_op,
)

from marblevideo.ops import REGISTRY
from marblevideo.recipe import parse_recipe

pytestmark = pytest.mark.tier("fast")

TESTS = ROOT / "tests"
#: The modules tests import (helpers, recipes, clips...), by their plain names.
SUPPORT = TESTS / "support"
#: The folders whose modules may be tempted to import the tests' conftest.
SOURCES = sorted(
    p
    for folder in ("tests", "benchmarks", "scripts", "samples")
    for p in (ROOT / folder).rglob("*.py")
)
#: The tests' own modules and their support, the helpers' module (where renderers
#: and PYTHONPATH are made) aside.
TEST_MODULES = sorted(p for p in TESTS.rglob("*.py") if p != SUPPORT / "helpers.py")
#: The modules pytest collects.
COLLECTED = sorted(p for p in TESTS.rglob("test_*.py") if SUPPORT not in p.parents)
IMPORTS_CONFTEST = re.compile(
    r"^\s*(from\s+(tests\.)?conftest\s+import|import\s+(tests\.)?conftest)\b", re.M
)

IMPORTS_A_TEST = re.compile(
    r"^\s*(from\s+(tests\.)?test_\w+\s+import|import\s+(tests\.)?test_\w+)", re.M
)


def imports_of_tests(text: str) -> list[str]:
    return [m.group(0).strip() for m in IMPORTS_A_TEST.finditer(text)]


def conftest_imports(text: str) -> list[str]:
    return [m.group(0).strip() for m in IMPORTS_CONFTEST.finditer(text)]


def tiers_declared(text: str) -> list[object]:
    """The tiers named by ``pytest.mark.tier(...)`` in a module's top-level
    ``pytestmark`` (one mark or a list of marks)."""
    found = []
    for node in ast.parse(text).body:
        targets = getattr(node, "targets", [])
        if isinstance(node, ast.Assign) and "pytestmark" in [ast.unparse(t) for t in targets]:
            value = node.value
            marks = value.elts if isinstance(value, ast.List | ast.Tuple) else [value]
            for mark in marks:
                if isinstance(mark, ast.Call) and ast.unparse(mark.func) == "pytest.mark.tier":
                    found += [a.value if isinstance(a, ast.Constant) else None for a in mark.args]
    return found


def renderers_made(text: str) -> list[int]:
    """Lines of ``Renderer(...)`` calls and of ``Marbler(recipe)`` ones (which make
    their own renderer on the default device); code in strings, run in a
    subprocess, aside."""
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Call):
            func = node.func
            called = func.id if isinstance(func, ast.Name) else getattr(func, "attr", None)
            given = len(node.args) > 1 or {k.arg for k in node.keywords} & {"renderer", "device"}
            if called == "Renderer" or (called == "Marbler" and not given):
                found.append(node.lineno)
    return found


def pythonpaths_by_hand(text: str) -> list[int]:
    """Lines setting PYTHONPATH (a dict key or a keyword) to anything but pythonpath()."""
    found = []
    for node in ast.walk(ast.parse(text)):
        pairs = []
        if isinstance(node, ast.Dict):
            items = zip(node.keys, node.values, strict=True)
            pairs = [(k.value, v) for k, v in items if isinstance(k, ast.Constant)]
        elif isinstance(node, ast.keyword):
            pairs = [(node.arg, node.value)]
        by_hand = [v for k, v in pairs if k == "PYTHONPATH" and ast.unparse(v) != "pythonpath()"]
        found += [v.lineno for v in by_hand]
    return found


def offenders(paths, check) -> dict[str, object]:
    found = {str(p.relative_to(ROOT)): check(p.read_text()) for p in paths}
    return {name: what for name, what in found.items() if what}


def test_every_test_module_declares_its_tier():
    """Each test module says whether it is in the fast tier (``pytest -m fast``) or
    the integration tier, once, in its ``pytestmark``: a new module is fast only if
    it says so, so a slow one cannot slow the edit loop unnoticed."""
    wrong = {}
    for path in COLLECTED:
        tiers = tiers_declared(path.read_text())
        if len(tiers) != 1 or tiers[0] not in TIERS:
            wrong[str(path.relative_to(ROOT))] = tiers
    assert not wrong, f"declare pytestmark = pytest.mark.tier(one of {TIERS}): {wrong}"


def test_support_modules_live_in_tests_support():
    """tests/ holds test modules and conftest.py only; what tests import lives in
    tests/support/ (no tests there), which pytest's ``pythonpath`` setting puts
    on the import path, so tests import it by plain name (``from helpers import``)."""
    loose = [p.name for p in TESTS.glob("*.py") if p not in COLLECTED and p.name != "conftest.py"]
    assert not loose, f"move to tests/support/: {loose}"
    assert not [p.name for p in SUPPORT.glob("*.py") if p.name.startswith(("test_", "conftest"))]
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "tests/support" in config["tool"]["pytest"]["ini_options"]["pythonpath"]


def test_nothing_imports_conftest():
    """Helpers live in modules (helpers.py, recipes.py...): pytest loads conftest.py
    itself, and a second import of it runs it twice under another name."""
    assert not offenders(SOURCES, conftest_imports)


def test_no_test_module_imports_another():
    """What two test modules share lives in a helpers module (helpers, live_helpers,
    recipes, sound...): importing a test module runs its module-level skips (an
    importorskip there skipped the importer too) and collects its tests twice."""
    found = offenders(TEST_MODULES, imports_of_tests)
    assert not found, f"a test module imported by another: {found}"


def test_conftest_defines_fixtures_and_hooks_only():
    names = []
    for node in ast.parse((TESTS / "conftest.py").read_text()).body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            fixture = any("fixture" in ast.unparse(d) for d in node.decorator_list)
            if not fixture and not node.name.startswith("pytest_"):
                names.append(node.name)
    assert not names, f"helpers belong in tests/support/: {names}"


def test_renderers_are_made_by_fresh_renderer():
    """Tests take the session's ``renderer`` fixture, or ``fresh_renderer()`` where
    they need a renderer of their own: both run on MARBLEVIDEO_TEST_DEVICE."""
    made = offenders(TEST_MODULES, renderers_made)
    assert not made, f"Renderer(...) made by hand (use helpers.fresh_renderer): {made}"


def test_subprocesses_take_pythonpath_from_the_helper():
    """PYTHONPATH is set only to helpers.pythonpath() (the checkout, then the
    caller's), never to the checkout alone."""
    bad = offenders(TEST_MODULES, pythonpaths_by_hand)
    assert not bad, f"PYTHONPATH set by hand (use helpers.subprocess_env): {bad}"


def test_the_layout_checks_find_what_they_look_for():
    code = (
        "from conftest import ROOT\nimport tests.conftest\n"
        "r = Renderer(lanes=1)\nenv = {'PYTHONPATH': str(ROOT)}\n"
        "run(env=dict(PYTHONPATH=ROOT))\nok = {'PYTHONPATH': pythonpath()}\n"
        "script = 'Renderer()'\nm = Marbler(recipe)\nok = Marbler(recipe, renderer)\n"
    )
    assert conftest_imports(code) == ["from conftest import", "import tests.conftest"]
    imports = "from test_uv import x\nimport tests.test_vector\nfrom testing import y\n"
    assert imports_of_tests(imports) == ["from test_uv import", "import tests.test_vector"]
    assert renderers_made(code) == [3, 8]
    tiers = 'import pytest\npytestmark = [pytest.mark.tier("fast"), pytest.mark.skipif(x)]\n'
    assert tiers_declared(tiers) == ["fast"]
    assert tiers_declared("pytestmark = pytest.mark.tier(TIER)\nx = pytest.mark.tier('a')") == [
        None
    ]
    assert tiers_declared("def f():\n    pytestmark = pytest.mark.tier('fast')\n") == []
    assert pythonpaths_by_hand(code) == [4, 5]


def test_random_recipes_cover_every_registered_type():
    """Every registered op type is drawn by random recipes (its own law or the
    generic one) unless recipes.NOT_RANDOM leaves it out with a reason; nothing
    listed is unregistered."""
    assert tuple(t for t in REGISTRY if t not in NOT_RANDOM) == OPS
    assert set(GENERATORS) | set(NOT_RANDOM) <= set(REGISTRY)
    assert set(GENERATORS).isdisjoint(NOT_RANDOM)
    assert all(reason.strip() for reason in NOT_RANDOM.values())


def test_a_new_op_type_is_drawn_with_nothing_edited():
    """A type only registered (a vortex renamed) is in random recipes, drawn by
    the generic law from its parameters' kinds into an op the recipe accepts."""
    whirl = replace(REGISTRY["vortex"], type="whirl")
    assert random_types({**REGISTRY, "whirl": whirl})[-1] == "whirl"
    assert generator("whirl") is valid_registry_op
    rng = np.random.default_rng(1)
    op = {"type": "vortex", **generator("whirl")(rng, "vortex", 160, 120)}
    parse_recipe({"canvas": [160, 120], "ops": [op]}, "r.json")


@pytest.mark.parametrize("seed", range(3))
def test_a_recipe_of_as_many_ops_as_types_holds_every_type(seed):
    recipe = random_recipe(seed, n_ops=len(OPS))
    assert sorted(op["type"] for op in recipe["ops"]) == sorted(OPS)
    parse_recipe(recipe, "random.json")
