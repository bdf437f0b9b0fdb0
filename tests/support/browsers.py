"""Headless Chromium for the page's tests (the conftest's ``browser`` fixtures)."""

from __future__ import annotations

import os
import shutil

import pytest


def chromium_browser(args: list[str]):
    """A headless Chromium driven by Playwright, launched with ``args``; the test
    is skipped, with the reason, when either is missing (``pip install
    playwright``; ``apt-get install chromium``; MARBLEVIDEO_CHROMIUM names another
    executable)."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    chromium = os.environ.get("MARBLEVIDEO_CHROMIUM") or shutil.which("chromium")
    if not chromium or not os.path.exists(chromium):
        pytest.skip("chromium is not installed (apt-get install chromium)")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium, args=args)
        yield b
        b.close()
