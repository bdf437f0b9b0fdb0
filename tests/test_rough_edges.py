"""Rough edges of the command line a new user meets (issue 34): what an unknown
output extension lists, interrupted banded stills, stills too big for their
format, a still of an animation that comes back to rest, and a blank sheet at
another aspect than its canvas. Each through the real command in a subprocess
(exit status and stderr are the contract) on the real OpenCL device."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from conftest import ROOT, files, one_line

from marblevideo.media.formats import (
    EXTENSION_FORMATS,
    IMAGE_EXTENSIONS,
    VECTOR_EXTENSIONS,
    output_kinds,
)


@pytest.mark.parametrize("src, dst", [(None, "o.xyz"), (None, "o"), ("in.mp4", "o.avi")])
def test_an_unknown_extension_lists_every_kind(cli, tmp_path, src, dst):
    """Stills, video, sequences and vectors, as --help lists them (one table)."""
    proc = cli(*([src] if src else []), "--ops", "figure6", "-o", dst)
    assert proc.returncode == 2
    line = one_line(proc)
    assert "unknown output extension" in line
    for ext in (*IMAGE_EXTENSIONS, *EXTENSION_FORMATS, *VECTOR_EXTENSIONS, "name_%04d.png"):
        assert f" {ext}" in line, ext
    assert output_kinds() in " ".join(cli("--help").stdout.split())
    assert files(tmp_path) == []


def _interrupt_banded(tmp_path: Path, name: str, sig: int) -> subprocess.CompletedProcess:
    """Render a big still in bands (small ones, through MARBLEVIDEO_BAND_PIXELS: the
    same code path as over 64 Mpixel), send ``sig`` once its first bands are on disk."""
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "marblevideo",
            "--ops",
            "figure6",
            "-o",
            name,
            "--size",
            "6000x6000",
            "--progress",
            "off",
        ],  # fmt: skip
        cwd=tmp_path,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT), "MARBLEVIDEO_BAND_PIXELS": "65536"},
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        parts = [p for p in tmp_path.iterdir() if ".part" in p.name]
        if parts and parts[0].stat().st_size > 100_000:
            break
        time.sleep(0.02)
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, "", err)


@pytest.mark.parametrize("name", ["big.png", "big.tif"])
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupting_a_banded_still(tmp_path, name, sig, code):
    """Ctrl-C or SIGTERM in the middle of a banded write: one line, 130/143, and
    neither the output nor its temporary file left."""
    proc = _interrupt_banded(tmp_path, name, sig)
    assert proc.returncode == code
    assert one_line(proc) == "marblevideo: interrupted"
    assert files(tmp_path) == []


@pytest.mark.parametrize(
    "args, fault",
    [
        (["-o", "a.jpg", "--size", "30000x20000"], "over 268435456 pixels"),
        (["-o", "a.webp", "--size", "20000x2000"], "over WebP's 16383 pixels a side"),
        (["-o", "-", "--format", "png", "--size", "20000x20000"], "to standard output"),
        (["in.png", "-o", "a.jpeg", "--size", "16385x16384"], "over 268435456 pixels"),
    ],
)
def test_a_still_too_big_for_its_format(cli, tmp_path, args, fault):
    """One line naming the formats that can (PNG, TIFF), before any work: before
    the device is chosen (an unknown one would fail) or the input is read."""
    proc = cli("--ops", "figure6", *args, "--device", "no-such-device")
    assert proc.returncode == 2
    line = one_line(proc)
    assert fault in line and "PNG and TIFF files are written in bands" in line
    assert files(tmp_path) == [] and proc.stdout == ""


def test_a_batch_of_stills_too_big_for_their_format(cli, tmp_path):
    cv2.imwrite(str(tmp_path / "a.png"), np.zeros((8, 8, 3), np.uint8))
    proc = cli("batch", "*.png", "--ops", "swirl", "-o", "{stem}.jpg", "--size", "30000x20000")
    assert proc.returncode == 2
    assert "a.jpg: 30000x20000 is over" in one_line(proc)
    assert files(tmp_path) == ["a.png"]
