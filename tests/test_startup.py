"""What every command pays before its first frame: the modules a render imports
leave SciPy out (``scipy.signal`` alone costs about 80 MB of peak memory and a
second of start-up; only a recipe that follows audio filters anything)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from helpers import ROOT, subprocess_env

pytestmark = pytest.mark.tier("fast")

#: the modules a still or video render imports on its way to the first frame
RENDER_MODULES = (
    "marblevideo.cli",
    "marblevideo.cli.render",
    "marblevideo.api",
    "marblevideo.scale.segmented",
    "marblevideo.signals.follow",
    "marblevideo.signals.audio",
)


def imported_after(modules: tuple[str, ...], then: str = "") -> set[str]:
    """The top-level packages in ``sys.modules`` of a fresh interpreter that imported
    ``modules`` and ran the statement ``then``."""
    code = (
        "import importlib, json, sys\n"
        f"for name in {list(modules)!r}: importlib.import_module(name)\n"
        f"{then}\n"
        "print(json.dumps(sorted({m.partition('.')[0] for m in sys.modules})))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=ROOT,
        env=subprocess_env(),
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    return set(json.loads(done.stdout))


def test_a_render_imports_no_scipy_until_a_recipe_follows_audio():
    assert "scipy" not in imported_after(RENDER_MODULES)


def test_a_filter_bank_brings_scipy_when_it_is_made():
    """The check above sees SciPy when it is there: a bank made imports it."""
    bank = "from marblevideo.signals.bands import FilterBank; FilterBank(48000.0)"
    assert "scipy" in imported_after(RENDER_MODULES, then=bank)
