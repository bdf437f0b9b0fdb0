"""A preset's name given to an editing session (``design``, ``live --preview``)
opens a working copy beside the user: never an empty file named after the
preset, never the installed sample; an existing copy is replaced only with -y."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys

import pytest
from helpers import ROOT, one_line, subprocess_env
from live_helpers import LiveProcess

pytestmark = pytest.mark.tier("integration")

SAMPLES = ROOT / "samples"


def digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def edit_and_stop(app: LiveProcess) -> dict:
    """PUT the recipe back with one op fewer; stop; the edited document."""
    doc = app.get("/api/recipe")
    doc["ops"] = doc["ops"][:-1]
    app.post("/api/recipe", doc, "PUT")
    assert app.stop() == 0, app.stderr()
    return doc


def test_design_edits_a_copy_of_the_preset(tmp_path):
    bundled = SAMPLES / "nonpareil.json"
    before = digest(bundled)
    app = LiveProcess(
        "--ops", "nonpareil", "--no-browser", "--port", "0", "--duration", "60",
        cwd=tmp_path, command="design",
    )  # fmt: skip
    try:
        copy = tmp_path / "nonpareil.json"
        assert json.loads(copy.read_text()) == json.loads(bundled.read_text())
        doc = edit_and_stop(app)
    finally:
        app.stop()
    assert "editing nonpareil.json, a copy of the preset 'nonpareil'" in app.stderr()
    assert json.loads(copy.read_text())["ops"] == doc["ops"]  # the copy took the edit
    assert digest(bundled) == before  # the sample did not
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".json") == [copy.name]
    assert not (tmp_path / "nonpareil").exists()  # no empty file named after the preset


def run(tmp_path, *args):
    return subprocess.run(
        [sys.executable, "-m", "marblevideo", *args],
        cwd=tmp_path, env=subprocess_env(), capture_output=True, text=True, timeout=120,
    )  # fmt: skip


def test_an_existing_copy_is_kept_without_y(tmp_path):
    copy = tmp_path / "swirl.json"
    copy.write_text('{"mine": true}')
    for command in (
        ["design", "--ops", "swirl", "--no-browser", "--port", "0", "--duration", "1"],
        ["live", "test", "--ops", "swirl", "--preview", "--port", "0", "--duration", "1"],
    ):
        proc = run(tmp_path, *command)
        assert proc.returncode == 2, proc.stderr
        line = one_line(proc)
        assert (
            "swirl.json: already exists" in line and "-y" in line and "--ops ./swirl.json" in line
        )
        assert copy.read_text() == '{"mine": true}'
    # a bad option is refused before the copy is written
    proc = run(tmp_path, "design", "--ops", "swirl", "-y", "--port", "70000", "--no-browser")
    assert proc.returncode == 2 and "--port" in one_line(proc)
    assert copy.read_text() == '{"mine": true}'
    proc = run(tmp_path, "design", "--ops", "swirl", "-y", "--no-browser", "--port", "0",
               "--duration", "1")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert json.loads(copy.read_text()) == json.loads((SAMPLES / "swirl.json").read_text())


def test_live_preview_edits_a_copy_and_plain_live_reads_the_preset(tmp_path):
    bundled = SAMPLES / "swirl.json"
    before = digest(bundled)
    app = LiveProcess(
        "test", "--ops", "swirl", "--size", "160x120", "--port", "0", "--preview",
        "--duration", "60", cwd=tmp_path,
    )  # fmt: skip
    try:
        doc = edit_and_stop(app)
    finally:
        app.stop()
    assert json.loads((tmp_path / "swirl.json").read_text())["ops"] == doc["ops"]
    assert digest(bundled) == before
    # without --preview nothing edits the recipe: the preset is read where it lies
    other = tmp_path / "plain"
    other.mkdir()
    proc = run(other, "live", "test", "--ops", "swirl", "--size", "160x120", "--duration", "1")
    assert proc.returncode == 0, proc.stderr
    assert list(other.iterdir()) == []


def test_the_bundled_file_by_path_is_a_preset_too(tmp_path):
    """``--ops samples/swirl.json`` (the README's live examples) edits ./swirl.json."""
    bundled = SAMPLES / "swirl.json"
    proc = run(tmp_path, "design", "--ops", str(bundled), "--no-browser", "--port", "0",
               "--duration", "1")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "swirl.json").read_bytes() == bundled.read_bytes()
    proc = run(SAMPLES, "design", "--ops", "swirl.json", "--no-browser", "--port", "0")
    assert proc.returncode == 2 and "is the bundled preset" in one_line(proc)
