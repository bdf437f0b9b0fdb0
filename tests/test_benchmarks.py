"""The benchmarks package starts (nothing is timed here): one runner, ``python -m
benchmarks PART``, every part's module importable, no sys.path edits, modules of
at most 400 lines."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest
from helpers import ROOT, subprocess_env

pytestmark = pytest.mark.tier("fast")

BENCHMARKS = ROOT / "benchmarks"
MODULES = sorted(p.stem for p in BENCHMARKS.glob("*.py"))


@pytest.mark.parametrize("name", MODULES)
def test_the_module_imports_as_part_of_the_package(name):
    text = (BENCHMARKS / f"{name}.py").read_text()
    assert "sys.path" not in text
    assert len(text.splitlines()) <= 400
    if name != "__main__":
        importlib.import_module(f"benchmarks.{name}")


def test_every_part_runs_functions_of_the_package():
    """Each part names functions that exist and argument forms the runner has (not run)."""
    from benchmarks.__main__ import PARTS, arguments, function, parser

    args = parser().parse_args(["--seconds", "1", "2"])
    for part, steps in PARTS.items():
        assert steps, part
        for module, name, form in steps:
            assert callable(function(module, name)), (part, module, name)
            assert arguments(form, args), (part, form)
    assert arguments("lengths", args) == [(None, 1), (None, 2)]


def test_the_runner_lists_its_parts_and_refuses_an_unknown_one():
    run = {"cwd": ROOT, "env": subprocess_env(), "capture_output": True, "text": True}
    helped = subprocess.run([sys.executable, "-m", "benchmarks", "--help"], timeout=60, **run)
    assert helped.returncode == 0 and "table1" in helped.stdout and "strokes" in helped.stdout
    refused = subprocess.run([sys.executable, "-m", "benchmarks", "nope"], timeout=60, **run)
    assert refused.returncode == 2 and "unknown part(s) nope" in refused.stderr


def test_compare_runs_two_commits_side_by_side_on_a_tiny_clip(capsys):
    """HEAD checked out into a temporary worktree against this checkout, one round."""
    from benchmarks.compare import compare

    before = temporary_trees()
    compare(None, ["HEAD"], seconds=1, rounds=1, size=(96, 64))
    out = capsys.readouterr().out
    assert "this checkout against HEAD (" in out
    rows = [line.split(" | ") for line in out.splitlines() if line.startswith("| static |")]
    rows += [line.split(" | ") for line in out.splitlines() if line.startswith("| animated |")]
    assert [r[1] for r in rows] == ["wall s", "CPU s", "peak RSS MB"] * 2
    assert all(float(r[2]) > 0 and float(r[3]) > 0 for r in rows)
    assert "load average" in out
    assert temporary_trees() == before  # its worktree removed after


def temporary_trees() -> set[str]:
    """The checkout's worktrees that compare made (named tree-COMMIT-...)."""
    listed = subprocess.run(
        ["git", "-C", str(ROOT), "worktree", "list"], capture_output=True, text=True, check=True
    )
    return {line.split()[0] for line in listed.stdout.splitlines() if "/tree-" in line}


def test_compare_needs_one_or_two_commits():
    run = {"cwd": ROOT, "env": subprocess_env(), "capture_output": True, "text": True}
    refused = subprocess.run([sys.executable, "-m", "benchmarks", "compare"], timeout=60, **run)
    assert refused.returncode == 2 and "compare BASE [HEAD]" in refused.stderr
    unknown = [sys.executable, "-m", "benchmarks", "compare", "no-such-commit", "--rounds", "1"]
    refused = subprocess.run(unknown, timeout=60, **run)
    assert refused.returncode == 1 and "no commit 'no-such-commit'" in refused.stderr
