"""Helpers that tests import: the checkout, subprocess environments, fresh renderers
and the checks of a failed run. conftest.py holds fixtures only (no test imports it).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

#: The checkout (the folder holding marblevideo/, tests/, benchmarks/).
ROOT = Path(__file__).resolve().parents[2]
#: The tiers a test module declares with ``pytestmark = pytest.mark.tier(NAME)``:
#: "fast" for the edit loop's tests (the recipe, the ops, the reference and the
#: kernels against it; ``pytest -m fast``), "integration" for modules that run
#: whole commands, servers, browsers, encoders or clusters.
TIERS = ("fast", "integration")


def device_choice() -> str | None:
    """The --device choice the tests run on: MARBLEVIDEO_TEST_DEVICE, else the default."""
    return os.environ.get("MARBLEVIDEO_TEST_DEVICE")


def fresh_renderer(**options):
    """A new Renderer on the test device, for tests of what one renderer keeps
    (caches, reused maps, programs built, counters) or of other options (lanes,
    chains, adaptive...); every other test takes the session's ``renderer`` fixture."""
    from marblevideo.opencl.renderer import Renderer

    return Renderer(device_choice(), **options)


def pythonpath() -> str:
    """The checkout first, then the caller's PYTHONPATH (packages installed with --target)."""
    return os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))


def subprocess_env(**extra: str) -> dict[str, str]:
    """This process's environment for a subprocess that imports the checkout
    (:func:`pythonpath`), with ``extra`` variables added."""
    return {**os.environ, "PYTHONPATH": pythonpath(), **extra}


def one_line(proc) -> str:
    """The single stderr line of a failed run (``marblevideo: ...``); no traceback."""
    assert "Traceback" not in proc.stderr, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("marblevideo: ")
    return lines[0]


def files(folder: Path) -> list[str]:
    """The names in ``folder``, sorted."""
    return sorted(p.name for p in folder.iterdir())


def identity_pass(w: int, h: int) -> tuple[np.ndarray, np.ndarray]:
    """u, v of a pass that shows the canvas as a plain w x h render would."""
    u = (np.arange(w) + 0.5) / w
    v = 1.0 - (np.arange(h) + 0.5) / h
    return np.broadcast_to(u, (h, w)).copy(), np.broadcast_to(v[:, None], (h, w)).copy()


def assert_refused(cli, folder: Path, text: str, path: str, expected: str, name: str = "") -> None:
    """``text`` as ``folder``/r.json, rendered through the CLI: refused with exit 2 in
    one line naming r.json and the JSON ``path``, holding ``expected``; nothing written."""
    (folder / "r.json").write_text(text)
    proc = cli("--ops", "r.json", "-o", "out.png")
    assert proc.returncode == 2, (name, proc.stderr)
    line = one_line(proc)
    assert line.startswith(f"marblevideo: r.json: {path}: "), (name, line)
    assert expected in line, (name, line)
    assert files(folder) == ["r.json"], name


def run_main(*argv: str):
    """The command line ``marblevideo ARGV`` run in this process (``cli.main``), as a
    CompletedProcess: its exit status and what it wrote to standard output (bytes
    through its buffer too, decoded) and error (text). What :func:`one_line` checks
    of a subprocess, it checks of this."""
    import contextlib
    import io
    import subprocess

    from marblevideo.cli import main

    out = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", write_through=True)
    err = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
        out.flush()
    text = out.buffer.getvalue().decode("utf-8", errors="replace")
    return subprocess.CompletedProcess(list(argv), status, text, err.getvalue())
