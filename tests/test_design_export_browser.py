"""The designer's Export links for the hosts (ffmpeg, GStreamer, ISF), clicked in a
real headless Chromium: each downloads what `marblevideo export` writes for the
design as it stands (a generator on a blank sheet), and a design a host cannot
carry says why over the sheet instead of downloading the error."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from live_helpers import designer_page, wait_for

from marblevideo.cli import main

pytestmark = pytest.mark.tier("integration")


def _exported(tmp_path: Path, recipe: Path, suffix: str, *options: str) -> str:
    out = tmp_path / f"cli{suffix}"
    assert main(["export", str(recipe), "-o", str(out), "-q", "-y", *options]) == 0
    return out.read_text()


DROP = {"type": "drop", "center": [100, 50], "radius": 30, "color": "#c03020"}


def _recipe_file(path: Path, ops: list, **more) -> Path:
    path.write_text(json.dumps({"marblevideo": 1, "canvas": [200, 100], "ops": ops, **more}))
    return path


def test_export_links_download_the_hosts_files(browser, tmp_path):
    wave = {"type": "wave", "amplitude": 6, "wavelength": 40, "phase": 0, "angle": 90}
    recipe = _recipe_file(tmp_path / "mine.json", [DROP, wave])
    with designer_page(browser, tmp_path, "--ops", recipe) as (page, errors):
        assert "marblevideo export" in page.text_content("#export-help")
        for link, suffix, options in [
            ("#export-cl", ".cl", ()),
            ("#export-frag", ".frag", ("--sheet",)),
            ("#export-vert", ".vert", ("--sheet",)),
            ("#export-fs", ".fs", ("--sheet",)),
        ]:
            with page.expect_download() as download:
                page.click(link)
            got = download.value
            assert got.suggested_filename == f"mine{suffix}"
            text = Path(got.path()).read_text()
            if suffix == ".vert":
                assert text == (tmp_path / "cli.vert").read_text()
            else:
                assert text == _exported(tmp_path, recipe, suffix, *options), suffix
        assert not errors


def test_a_design_a_host_cannot_carry_says_why(browser, tmp_path):
    recipe = _recipe_file(tmp_path / "moving.json", [DROP], motion={})
    with designer_page(browser, tmp_path, "--ops", recipe) as (page, errors):
        page.click("#export-cl")
        wait_for(lambda: "export:" in page.inner_text("#error"), "the export's error")
        assert "motion" in page.inner_text("#error")
        assert [e for e in errors if "400" not in e] == []
