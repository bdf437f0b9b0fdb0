"""Rough edges of the command line a new user meets: what an unknown
output extension lists, interrupted banded stills, stills too big for their
format, a still of an animation that comes back to rest, and a blank sheet at
another aspect than its canvas. Each through the real command in a subprocess
(exit status and stderr are the contract) on the real OpenCL device."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers import files, one_line, subprocess_env
from interrupts import interrupt, wait_until
from recipes import make_image
from tolerances import KERNEL_SHARE

from marblevideo.marbler import Marbler
from marblevideo.media.formats import (
    EXTENSION_FORMATS,
    IMAGE_EXTENSIONS,
    VECTOR_EXTENSIONS,
    output_kinds,
)
from marblevideo.opencl.selfcheck import agreement
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import Geometry
from marblevideo.reference import render as reference_render
from marblevideo.reference.motion import rest_note

pytestmark = pytest.mark.tier("fast")


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
        env=subprocess_env(MARBLEVIDEO_BAND_PIXELS="65536"),
    )

    def writing() -> bool:
        parts = [p for p in tmp_path.iterdir() if ".part" in p.name]
        return bool(parts) and parts[0].stat().st_size > 100_000

    wait_until(proc, writing, 120)
    return interrupt(proc, sig)


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


# ---------------------------------------------------------------- a still at rest


def _wave(keys: list[tuple[float, float]]) -> dict:
    amplitude = {"keys": [{"t": t, "v": v} for t, v in keys]}
    wave = {"type": "wave", "amplitude": amplitude, "wavelength": 32, "phase": 0, "angle": 0}
    return {"canvas": [64, 48], "antialias": "none", "ops": [wave]}


@pytest.mark.parametrize(
    "keys, strongest",
    [
        ([(0, 0), (2, 10), (4, 0)], "2"),
        ([(0, 0), (1, 12), (3, 1.2)], "1"),
        ([(0, 0), (1, 12), (3, 6)], None),
        ([(0, 0), (4, 12)], None),
    ],
)
def test_a_still_at_the_end_of_an_animation_back_at_rest(keys, strongest):
    recipe = parse_recipe(_wave(keys), "v.json")
    note = rest_note(recipe, recipe.canvas)
    if strongest is None:
        assert note is None
    else:
        assert note.startswith("v.json: the still is taken at the animation's end")
        assert f"strongest at {strongest} s (--time {strongest})" in note


def test_the_rest_note_says_what_the_still_shows(cli, tmp_path, renderer):
    """swirl over a picture: at its end (the default) the still is nearly the
    picture, at the time the note names it is marbled; the note goes with the
    default time only."""
    picture = make_image(160, 90)
    cv2.imwrite(str(tmp_path / "in.png"), cv2.cvtColor(picture, cv2.COLOR_RGBA2BGR))
    proc = cli("in.png", "--ops", "swirl", "-o", "end.png")
    assert proc.returncode == 0, proc.stderr
    note = proc.stderr.splitlines()[0]
    assert "swirl.json: the still is taken at the animation's end (6 s)" in note
    assert note.endswith("strongest at 3 s (--time 3)")
    proc = cli("in.png", "--ops", "swirl", "-o", "at3.png", "--time", "3")
    assert proc.returncode == 0 and proc.stderr.splitlines() == ["wrote at3.png"]
    plain = cv2.imread(str(tmp_path / "in.png")).astype(int)
    moved = [
        np.abs(cv2.imread(str(tmp_path / name)).astype(int) - plain).mean()
        for name in ("end.png", "at3.png")
    ]
    assert moved[0] * 3 < moved[1]
    proc = cli("--ops", "figure6", "-o", "f.png", "--size", "64x64")
    assert proc.stderr.splitlines() == ["wrote f.png"]


# ---------------------------------------------------------- a blank sheet's aspect

SHEET = {
    "canvas": [64, 48],
    "antialias": "none",
    "background": "#f0e8d8",
    "ops": [
        {"type": "drop", "center": [8, 8], "radius": 10, "color": "#203080"},
        {"type": "drop", "center": [56, 40], "radius": 10, "color": "#a03020"},
        {"type": "comb", "point": [0, 24], "angle": 0, "spacing": 12, "alpha": 20, "lambda": 8},
    ],
}


def _expected_geometry(fit: str | None, w: int, h: int) -> Geometry:
    """The canvas 64 x 48 in w x h, from the definitions: the contract's uniform
    scale to fit (default and pad), to cover (crop), per axis (stretch); centred."""
    sx, sy = w / 64, h / 48
    if fit in (None, "pad", "crop"):
        sx = sy = (min if fit != "crop" else max)(sx, sy)
    dx, dy = (w - 64 * sx) / 2, (h - 48 * sy) / 2
    return Geometry(w, h, (1 / sx, 1 / sy, -dx / sx, -dy / sy), (sx, sy, dx, dy))


@pytest.mark.parametrize("fit", [None, "pad", "crop", "stretch"])
@pytest.mark.parametrize("size", [(96, 32), (40, 80)])
def test_fit_places_a_blank_canvas(renderer, fit, size):
    recipe = parse_recipe(SHEET, "sheet.json")
    out = Marbler(recipe, renderer, fit=fit).render(None, None, size)
    expected = reference_render(recipe.at(0, recipe.canvas), _expected_geometry(fit, *size))
    assert agreement(out, expected) >= KERNEL_SHARE


def test_a_blank_sheet_at_another_aspect_says_so(cli, tmp_path):
    (tmp_path / "sheet.json").write_text(json.dumps(SHEET))
    proc = cli("--ops", "sheet.json", "-o", "wide.png", "--size", "96x32")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.splitlines() == [
        "marblevideo: canvas 64x48 fitted into 96x32 and centred (another aspect: what the ops "
        "carry past the canvas may be cut; --fit crop fills the frame, stretch distorts)",
        "wrote wide.png",
    ]
    for fit in ("pad", "crop", "stretch"):
        proc = cli("--ops", "sheet.json", "-o", f"{fit}.png", "--size", "96x32", "--fit", fit)
        assert proc.stderr.splitlines() == [f"wrote {fit}.png"], fit
    assert _pixels(tmp_path / "pad.png") == _pixels(tmp_path / "wide.png")  # the contract's
    assert _pixels(tmp_path / "crop.png") != _pixels(tmp_path / "wide.png")
    proc = cli("--ops", "sheet.json", "-o", "same.png", "--size", "128x96")
    assert proc.stderr.splitlines() == ["wrote same.png"]
    proc = cli("--ops", "sheet.json", "-o", "v.mp4", "--size", "96x32", "--fit", "crop",
               "--duration", "0.2")  # fmt: skip
    assert proc.returncode == 0 and "fitted" not in proc.stderr, proc.stderr
    proc = cli("--ops", "sheet.json", "-o", "v.svg", "--size", "96x32", "--fit", "crop")
    assert proc.returncode == 2 and "--fit" in one_line(proc)
    proc = cli("--ops", "sheet.json", "-o", "z.png", "--size", "96x32", "--fit", "crop",
               "--view", "0,0,32,24")  # fmt: skip
    assert proc.returncode == 2 and "--fit: --view places" in one_line(proc)


def _pixels(path: Path) -> bytes:
    return cv2.imread(str(path), cv2.IMREAD_UNCHANGED).tobytes()
