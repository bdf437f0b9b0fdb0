"""The tests' own shape: conftest.py holds fixtures only and no module imports it;
renderers are made by one helper (on the test device); subprocesses get the
checkout's PYTHONPATH from one helper."""

from __future__ import annotations

import ast
import re

import pytest
from helpers import ROOT

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
