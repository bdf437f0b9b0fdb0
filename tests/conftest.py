"""Shared fixtures and the tier hook (fixtures only: the modules tests import live
in tests/support/, on the import path by their plain names): one OpenCL renderer
per session on the real device.

The device comes from MARBLEVIDEO_TEST_DEVICE (a --device choice) or the
default choice (PoCL on a machine without a GPU). Nothing is mocked.
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from browsers import chromium_browser
from helpers import ROOT, TIERS, fresh_renderer, subprocess_env
from hypothesis import settings

# CI sees the same examples on every run, and no wall-clock deadline (a shared
# 2-core machine); locally, `HYPOTHESIS_PROFILE=dev` explores afresh.
settings.register_profile("ci", derandomize=True, database=None, deadline=None)
settings.register_profile("dev", deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

#: Fixtures that make a test an integration test wherever it is.
INTEGRATION_FIXTURES = {"cli", "browser"}


def pytest_collection_modifyitems(items):
    """Mark the ``fast`` tier (``pytest -m fast``): the tests of modules declaring
    ``tier("fast")``, less those marked ``slow`` and those taking the ``cli`` or
    ``browser`` fixture. A module that declares no tier is not fast."""
    for item in items:
        tier = item.get_closest_marker("tier")
        name = tier.args[0] if tier and tier.args else None
        if tier is not None and name not in TIERS:
            raise pytest.UsageError(f"{item.nodeid}: tier {name!r} is not one of {TIERS}")
        if (
            name == "fast"
            and not INTEGRATION_FIXTURES.intersection(getattr(item, "fixturenames", ()))
            and item.get_closest_marker("slow") is None
        ):
            item.add_marker(pytest.mark.fast)


@pytest.fixture(scope="session")
def renderer():
    """The session's renderer on the test device (MARBLEVIDEO_TEST_DEVICE); tests
    of what a renderer keeps, or of other options, take ``fresh_renderer()``."""
    return fresh_renderer()


@pytest.fixture(scope="session")
def one_pixel_renderer():
    """The session's renderer of the one-pixel code (lanes=1, chains=1: a GPU's)
    on the test device, for kernel tests that need no fresh renderer."""
    return fresh_renderer(lanes=1, chains=1)


@pytest.fixture(scope="module")
def browser():
    """A headless Chromium (:func:`browsers.chromium_browser`)."""
    yield from chromium_browser(["--no-sandbox"])


@pytest.fixture(scope="module")
def webgl_browser():
    """A headless Chromium with SwiftShader's WebGL2 allowed (the page's warp)."""
    from benchmarks.webfolder import ARGS

    yield from chromium_browser(ARGS)


@pytest.fixture
def cli(tmp_path):
    """Run the real command line in a subprocess; returns CompletedProcess."""

    def run(*args, cwd=None, timeout=300, input: bytes | None = None, env=None):  # noqa: A002
        """``input``: bytes for standard input; the output is then bytes too;
        ``env``: variables added to the environment."""
        return subprocess.run(
            [sys.executable, "-m", "marblevideo", *map(str, args)],
            cwd=cwd or tmp_path,
            input=input,
            capture_output=True,
            text=input is None,
            timeout=timeout,
            env=subprocess_env(**(env or {})),
        )

    return run


@pytest.fixture
def coffee_designer(browser, tmp_path):
    """``marblevideo design`` over samples/coffee.jpg with a 400x300 canvas (shown
    at 4/3 and centred in the 600x400 frame) and its page, once that shows an exact
    frame of the saved recipe: a namespace of ``recipe`` (the file), ``saved()``
    (its ops), ``page``, ``errors`` (the page's), ``s``, ``dx``, ``dy`` (frame
    pixel = s * canvas point + (dx, dy)) and ``client(px, py)`` (the page point
    over frame pixel (px, py)). The designer must then exit with status 0."""
    import json
    from types import SimpleNamespace

    from live_helpers import designer_page

    from marblevideo.recipe.frame import fit

    recipe, coffee = tmp_path / "coffee.json", ROOT / "samples" / "coffee.jpg"
    args = (coffee, "--ops", recipe, "--canvas", "400x300")
    with designer_page(browser, tmp_path, *args, duration=120) as (page, errors):
        page.wait_for_function(
            """() => { const d = document.getElementById('sheet').dataset;
                return Number(d.frames) > 0 && d.draft === '0' && d.shown === 'all'
                    && d.version === String(designer.state.version); }"""
        )
        box = page.locator("#overlay").bounding_box()

        def client(px: float, py: float) -> tuple[float, float]:
            return box["x"] + px * box["width"] / 600, box["y"] + py * box["height"] / 400

        s, dx, dy = fit((400, 300), 600, 400)
        saved = lambda: json.loads(recipe.read_text())["ops"]  # noqa: E731
        yield SimpleNamespace(
            recipe=recipe, saved=saved, page=page, errors=errors, s=s, dx=dx, dy=dy, client=client
        )
