"""What docstrings and docs cite holds: every dotted ``marblevideo.<module>.<name>`` name in
the docstrings of marblevideo/, tests/ and benchmarks/, in docs/*.md and in
README.md names a module or an attribute of one (a dataclass field counts), so a
moved or renamed part shows here; and no docstring cites an issue number (a
docstring says what the code does, the history lives in git)."""

from __future__ import annotations

import ast
import functools
import importlib
import importlib.util
import re
from pathlib import Path

import pytest
from helpers import ROOT

pytestmark = pytest.mark.tier("fast")

#: A dotted name of the package (not part of a path or a longer word).
DOTTED = re.compile(r"(?<![\w./-])marblevideo(?:\.[A-Za-z_]\w*)+")
#: "issue 22", "issues #3", "(#31)": a reference to the tracker.
ISSUE = re.compile(r"\bissues?\s+#?\d+|(?<![\w&#])#\d{1,4}(?![\w])", re.I)
PYTHON_FOLDERS = ("marblevideo", "tests", "benchmarks", "scripts", "samples")


@functools.cache
def docstrings(path: Path) -> list[tuple[int, str]]:
    """(line, text) of the module's, its classes' and its functions' docstrings."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            text = ast.get_docstring(node, clean=False)
            if text:
                found.append((node.body[0].lineno, text))
    return found


def python_sources(folders=PYTHON_FOLDERS) -> list[Path]:
    return sorted(p for folder in folders for p in (ROOT / folder).rglob("*.py"))


@functools.cache
def cited_texts() -> list[tuple[str, str]]:
    """(where, text) of every docstring that names parts and of every doc page."""
    texts = [
        (f"{path.relative_to(ROOT)}:{line}", text)
        for path in python_sources(("marblevideo", "tests", "benchmarks"))
        for line, text in docstrings(path)
    ]
    pages = [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]
    return texts + [(str(p.relative_to(ROOT)), p.read_text()) for p in pages]


def _module_of(parts: list[str]):
    """The longest importable module of ``parts``, with the names left after it."""
    for i in range(len(parts), 0, -1):
        try:
            spec = importlib.util.find_spec(".".join(parts[:i]))
        except ModuleNotFoundError:  # a prefix names a module, not a package
            continue
        if spec is not None:
            return importlib.import_module(".".join(parts[:i])), parts[i:]
    return None, parts


def resolves(name: str) -> bool:
    """Whether ``name`` is a module, or an attribute (or a dataclass field, an
    annotated class attribute) reached from one."""
    obj, rest = _module_of(name.split("."))
    if obj is None:
        return False
    for k, attr in enumerate(rest):
        if hasattr(obj, attr):
            obj = getattr(obj, attr)
            continue
        declared = isinstance(obj, type) and any(
            attr in getattr(c, "__annotations__", {}) for c in obj.__mro__
        )
        return declared and k == len(rest) - 1
    return True


def test_every_dotted_name_resolves():
    stale = {}
    for where, text in cited_texts():
        names = sorted({n for n in DOTTED.findall(text) if not resolves(n)})
        if names:
            stale[where] = names
    assert not stale, f"dotted names that name nothing (moved or renamed?): {stale}"


def test_the_name_check_sees_names_and_tells_them_apart():
    names = {n for _, text in cited_texts() for n in DOTTED.findall(text)}
    assert len(names) > 100 and "marblevideo.ops.REGISTRY" in names
    assert resolves("marblevideo.opencl.selfcheck_cases")  # a module never imported yet
    assert resolves("marblevideo.ops.OpDef.slots")  # a dataclass field
    assert resolves("marblevideo.recipe.frame.FrameSpec")
    assert not resolves("marblevideo.video.plan_output")
    assert not resolves("marblevideo.ops.OpDef.slots.count")
    assert not resolves("marblevideo.ops.NoSuchDef")
    text = "see marblevideo.api.render_still. Not samples/marblevideo.json, x.marblevideo.y"
    assert DOTTED.findall(text) == ["marblevideo.api.render_still"]


def test_no_docstring_cites_an_issue_number():
    cited = {
        f"{path.relative_to(ROOT)}:{line}": ISSUE.findall(text)
        for path in python_sources()
        for line, text in docstrings(path)
        if ISSUE.search(text)
    }
    assert not cited, f"say what is checked or done, not which issue asked: {cited}"


def test_the_issue_check_finds_what_it_looks_for():
    text = "Colours (issue 22), issue #31 and issues 3 (#7); not #1d3557, #fff or &#38;"
    assert ISSUE.findall(text) == ["issue 22", "issue #31", "issues 3", "#7"]
