"""Two commits' end-to-end commands side by side, paired and alternating.

    python -m benchmarks compare BASE [HEAD] --seconds 10 [--rounds 5]

BASE (and HEAD, if given; else this checkout as it is, uncommitted changes
included) is checked out into a temporary git worktree; the CLI of each tree
(``python -m marblevideo``, the tree first on PYTHONPATH, the same Python and
installed dependencies) marbles the e2e clip with the static and the animated
12-op recipe, after one warm-up run each, in rounds of A B A B. Each run is
one process measured by the operating system (os.wait4): wall seconds, CPU
seconds (user + system, of the process and its threads) and peak RSS. The
report gives each figure's median for both trees and the median of the
paired ratios HEAD / BASE, with the load average before and after: on a
shared machine the CPU time and the pairs are steadier than the wall time.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import tempfile
import time
from contextlib import ExitStack, contextmanager
from pathlib import Path

from .common import ROOT, animated12, make_clip, marble_command, recipe12

#: the figures of each run, in the report's order
FIGURES = ("wall s", "CPU s", "peak RSS MB")


@contextmanager
def checked_out(ref: str | None, folder: Path):
    """The tree of ``ref`` in a temporary worktree under ``folder`` (removed
    after; a folder of its own, so BASE and HEAD may be the same commit), or
    this checkout for None; yields (label, path)."""
    if ref is None:
        yield "this checkout", ROOT
        return
    git = ["git", "-C", str(ROOT)]
    commit = subprocess.run(
        [*git, "rev-parse", "--short", f"{ref}^{{commit}}"], capture_output=True, text=True
    )
    if commit.returncode:
        raise SystemExit(f"benchmarks compare: no commit {ref!r} in {ROOT}")
    path = Path(tempfile.mkdtemp(prefix=f"tree-{commit.stdout.strip()}-", dir=folder))
    add = [
        *git,
        "worktree",
        "add",
        "--detach",
        "--quiet",
        "--force",
        str(path),
        commit.stdout.strip(),
    ]
    subprocess.run(add, check=True)
    try:
        yield f"{ref} ({commit.stdout.strip()})", path
    finally:
        subprocess.run([*git, "worktree", "remove", "--force", str(path)], check=False)


def measured(cmd: list[str], tree: Path) -> tuple[float, float, float]:
    """(wall s, CPU s, peak RSS MB) of ``cmd`` run in ``tree`` with ``tree`` first on
    PYTHONPATH; SystemExit if it fails."""
    env = dict(
        os.environ,
        PYTHONPATH=os.pathsep.join(filter(None, [str(tree), os.environ.get("PYTHONPATH")])),
    )
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    began = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=tree, env=env, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - began
    if status:
        raise SystemExit(f"benchmarks compare: failed in {tree}: {' '.join(cmd)}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def compare(
    device: str | None, refs: list[str], seconds: int, rounds: int = 5, size=(1280, 720)
) -> None:
    """See the module: ``refs`` is [BASE] or [BASE, HEAD]."""
    with tempfile.TemporaryDirectory() as tmp, ExitStack() as stack:
        tmp = Path(tmp)
        trees = [stack.enter_context(checked_out(ref, tmp)) for ref in (refs + [None])[:2]]
        clip = make_clip(tmp / "clip.mp4", size=size, seconds=seconds)
        commands = {}
        for name, recipe in (("static", recipe12("rgss")), ("animated", animated12(seconds))):
            (tmp / f"{name}.json").write_text(json.dumps(recipe))
            commands[name] = marble_command(clip, tmp / f"{name}.json", tmp / "out.mp4", device)
        load = os.getloadavg()
        for cmd in commands.values():  # warm-up: kernel caches, imports
            for _, tree in trees:
                measured(cmd, tree)
        runs = {(name, k): [] for name in commands for k in range(2)}
        for _ in range(rounds):
            for name, cmd in commands.items():
                for k, (_, tree) in enumerate(trees):
                    runs[name, k].append(measured(cmd, tree))
        _report(trees, runs, list(commands), (size, seconds, rounds), (load, os.getloadavg()))


def _report(trees, runs: dict, names: list[str], case, loads) -> None:
    (w, h), seconds, rounds = case
    (base, _), (head, _) = trees
    print(f"\n## {head} against {base}: the CLI on a {w}x{h} clip of {seconds} s")
    print(f"12 ops RGSS, x264 veryfast crf 23; {rounds} paired rounds (A B A B), medians")
    print("| command | figure | base | head | head / base (median of pairs) |")
    print("|---|---|---|---|---|")
    for name in names:
        a, b = runs[name, 0], runs[name, 1]
        for i, figure in enumerate(FIGURES):
            ratios = [y[i] / x[i] for x, y in zip(a, b, strict=True)]
            med_a, med_b = statistics.median(r[i] for r in a), statistics.median(r[i] for r in b)
            print(
                f"| {name} | {figure} | {med_a:.2f} | {med_b:.2f} | "
                f"{statistics.median(ratios):.3f} ({min(ratios):.3f}-{max(ratios):.3f}) |"
            )
    before, after = (" ".join(f"{x:.1f}" for x in load) for load in loads)
    print(f"load average (1, 5, 15 min): {before} before, {after} after")
