"""What every command pays before its first frame: the modules a render imports
leave SciPy out (``scipy.signal`` alone costs about 80 MB of peak memory and a
second of start-up; only a recipe that follows audio filters anything);
``--version`` and ``--help`` import nothing heavy, a still of a blank sheet no
PyAV or OpenCV, and a recipe file read before no jsonschema (the times these
keep are in BENCHMARKS.md, start-up: the mechanism is tested here, not the clock)."""

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


def imported_after(
    modules: tuple[str, ...], then: str = "", env: dict[str, str] | None = None
) -> set[str]:
    """The top-level packages in ``sys.modules`` of a fresh interpreter that imported
    ``modules`` and ran the statement ``then`` (with ``env`` added to the environment)."""
    code = (
        "import importlib, json, sys\n"
        f"for name in {list(modules)!r}: importlib.import_module(name)\n"
        f"{then}\n"
        "print(json.dumps(sorted({m.partition('.')[0] for m in sys.modules})))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=ROOT,
        env=subprocess_env(**(env or {})),
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    return set(json.loads(done.stdout.splitlines()[-1]))  # after what ``then`` printed


def test_a_render_imports_no_scipy_until_a_recipe_follows_audio():
    assert "scipy" not in imported_after(RENDER_MODULES)


def test_a_filter_bank_brings_scipy_when_it_is_made():
    """The check above sees SciPy when it is there: a bank made imports it."""
    bank = "from marblevideo.signals.bands import FilterBank; FilterBank(48000.0)"
    assert "scipy" in imported_after(RENDER_MODULES, then=bank)


#: what a command that draws nothing needs none of
HEAVY = ("numpy", "pyopencl", "av", "cv2", "jsonschema", "scipy", "tqdm", "PIL")


@pytest.mark.parametrize(
    "then",
    [
        "",
        "import marblevideo; marblevideo.__version__",
        "from marblevideo.cli import main\ntry: main(['--version'])\nexcept SystemExit: pass",
        "from marblevideo.cli import main\ntry: main(['--help'])\nexcept SystemExit: pass",
    ],
    ids=["import-cli", "import-package", "version", "help"],
)
def test_version_and_help_import_nothing_heavy(then):
    """``marblevideo --version`` and ``--help`` answer in a few hundredths of a second
    (BENCHMARKS.md, start-up): neither NumPy nor OpenCL nor PyAV is loaded for them."""
    assert not imported_after(("marblevideo.cli",), then=then) & set(HEAVY)


def test_a_blank_still_imports_no_video_and_no_schema_the_second_time(tmp_path):
    """A PNG still of a blank sheet loads neither PyAV nor OpenCV (its PNG is small
    enough for zlib alone), and a recipe file read before skips jsonschema: the
    schema's acceptance of that text is kept (marblevideo.recipe.accepted)."""
    recipe = tmp_path / "r.json"
    recipe.write_text((ROOT / "samples" / "figure6.json").read_text())
    argv = ["--ops", str(recipe), "-o", str(tmp_path / "x.png"), "--size", "64x64", "-y", "-q"]
    run = f"from marblevideo.cli import main\nassert main({argv!r}) == 0"
    cache = {"MARBLEVIDEO_CACHE": str(tmp_path / "cache")}
    first = imported_after(("marblevideo.cli",), then=run, env=cache)
    assert "jsonschema" in first  # the check sees it when it is there
    again = imported_after(("marblevideo.cli",), then=run, env=cache)
    assert {"numpy", "pyopencl"} <= again
    assert not again & {"av", "cv2", "jsonschema", "scipy"}


def test_a_recipe_file_changed_is_validated_again(tmp_path, monkeypatch):
    """The kept acceptance is of the file's text: an edit that breaks it is refused
    with the schema's message, as on the first read; a refusal is not kept."""
    from marblevideo.errors import RecipeError
    from marblevideo.recipe.accepted import is_accepted, text_digest
    from marblevideo.recipe.load import read_recipe

    monkeypatch.setenv("MARBLEVIDEO_CACHE", str(tmp_path / "cache"))
    recipe = tmp_path / "r.json"
    recipe.write_text('{"ops": []}')
    read_recipe(recipe)
    assert is_accepted(text_digest('{"ops": []}'))
    read_recipe(recipe)  # accepted before: the schema is skipped
    broken = '{"ops": [], "fps": 3}'
    recipe.write_text(broken)
    for _ in range(2):
        with pytest.raises(RecipeError, match="fps"):
            read_recipe(recipe)
    assert not is_accepted(text_digest(broken))


def test_no_cache_when_it_is_off(tmp_path, monkeypatch):
    """``MARBLEVIDEO_CACHE=off`` keeps nothing: every read validates."""
    from marblevideo.recipe.accepted import is_accepted, text_digest
    from marblevideo.recipe.load import read_recipe

    monkeypatch.setenv("MARBLEVIDEO_CACHE", "off")
    recipe = tmp_path / "r.json"
    recipe.write_text('{"ops": []}')
    read_recipe(recipe)
    assert not is_accepted(text_digest('{"ops": []}'))
