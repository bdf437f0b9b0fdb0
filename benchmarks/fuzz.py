"""``python -m benchmarks fuzz --minutes N [HARNESS ...]``: each Hypothesis harness
(the pst-marble importer, the command line, the exports, the HTTP API; the
recipe loader on request) run for N minutes with a fresh seed, under the memory
and time limits its tests set (tests/support/fuzz_campaign.py drives pytest);
a Markdown table of executions per second, inputs tried and findings. A
finding is kept: the harness's test fails, its falsifying input printed, to be
fixed with an entry in tests/data/fuzz/ that the ordinary tests replay."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PATHS = (str(ROOT), str(ROOT / "tests" / "support"))  # the plugin is tests/support/fuzz_campaign.py
#: harness -> its tests (their node ids); the minutes are shared among them.
HARNESSES = {
    "importer": [
        "tests/test_fuzz_inputs.py::test_generated_designs_import_or_are_refused_in_one_line",
        "tests/test_fuzz_inputs.py::test_arbitrary_bytes_import_or_are_refused",
    ],
    "command line": [
        "tests/test_fuzz_inputs.py::test_render_command_lines_run_or_are_refused_in_one_line",
        "tests/test_fuzz_inputs.py::test_other_command_lines_run_or_are_refused_in_one_line",
    ],
    "exports": ["tests/test_export_hostile.py::test_hostile_recipes_export_or_are_refused"],
    "HTTP API": ["tests/test_api_fuzz.py::test_every_answer_is_well_formed"],
    "recipes": [
        "tests/test_fuzz_recipes.py::test_arbitrary_json_parses_or_is_refused_with_a_path",
        "tests/test_fuzz_recipes.py::test_mutated_recipes_render_or_are_refused_with_a_path",
    ],
}
DEFAULT = ("importer", "command line", "exports", "HTTP API")


def campaign(node: str, seconds: float) -> dict:
    """One harness test run for ``seconds``: its stats (inputs, seconds, findings) and
    pytest's exit status."""
    with tempfile.TemporaryDirectory(prefix="marblevideo-fuzz-") as tmp:
        report = Path(tmp) / "report.json"
        env = {
            **os.environ,
            "MARBLEVIDEO_FUZZ_SECONDS": str(seconds),
            "MARBLEVIDEO_FUZZ_REPORT": str(report),
            "PYTHONPATH": os.pathsep.join(filter(None, [*PATHS, os.environ.get("PYTHONPATH")])),
        }
        base = str(Path(tmp) / "t")
        cmd = [sys.executable, "-m", "pytest", node, "-q", "-p", "fuzz_campaign",
               "-p", "no:cacheprovider", "--basetemp", base, "--timeout", "0"]  # fmt: skip
        start = time.monotonic()
        proc = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
        wall = time.monotonic() - start
        stats = json.loads(report.read_text()).get(node, {}) if report.exists() else {}
    stats.setdefault("inputs", 0)
    stats.setdefault("findings", [])
    if proc.returncode != 0 and not stats["findings"]:
        last = [line for line in proc.stdout.splitlines() if line.strip()][-3:]
        stats["findings"] = [f"pytest exit {proc.returncode}: {' / '.join(last)[:400]}"]
    return {**stats, "wall": wall, "rc": proc.returncode, "log": proc.stdout}


def main(minutes: float, names: list[str]) -> int:
    """Run the harnesses ``names`` (default: :data:`DEFAULT`) for ``minutes`` each; print
    the table; 1 when any finding came, else 0."""
    names = names or list(DEFAULT)
    print(f"Fuzz campaign: {minutes:g} min per harness, fresh seeds\n")
    print("| harness | test | inputs | seconds | inputs/s | findings |")
    print("|---|---|---:|---:|---:|---|")
    found = 0
    for name in names:
        nodes = HARNESSES[name]
        for node in nodes:
            s = campaign(node, minutes * 60 / len(nodes))
            seconds = s.get("seconds") or s["wall"]
            rate = s["inputs"] / seconds if seconds else 0.0
            findings = "; ".join(s["findings"]) or "none"
            found += bool(s["findings"])
            test = node.split("::")[1]
            numbers = f"{s['inputs']:,} | {seconds:.0f} | {rate:.1f}"
            print(f"| {name} | `{test}` | {numbers} | {findings} |", flush=True)
            if s["rc"] != 0:
                print(s["log"][-3000:], file=sys.stderr)
    return 1 if found else 0
