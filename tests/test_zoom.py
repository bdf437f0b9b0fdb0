"""Deep zoom (--view) and big outputs rendered in bands and written progressively."""

from __future__ import annotations

import struct

import cv2
import numpy as np
import pytest

from marblevideo.api import render_still
from marblevideo.marbler import Marbler
from marblevideo.media.tiled import write_bands

pytestmark = pytest.mark.tier("fast")

FIGURE6 = "samples/figure6.json"


def read_rgb(path) -> np.ndarray:
    return cv2.cvtColor(cv2.imread(str(path), cv2.IMREAD_UNCHANGED), cv2.COLOR_BGR2RGB)


def on_edge(img: np.ndarray, mask: np.ndarray) -> bool:
    """Whether every pixel of ``mask`` lies within one pixel of a colour edge of ``img``
    (a float32 last-bit difference can only flip a subsample at an ink boundary,
    which may be a sliver thinner than a pixel)."""
    diff = np.zeros(img.shape[:2], bool)
    change = np.any(img[1:] != img[:-1], -1)
    diff[1:] |= change
    diff[:-1] |= change
    change = np.any(img[:, 1:] != img[:, :-1], -1)
    diff[:, 1:] |= change
    diff[:, :-1] |= change
    near = cv2.dilate(diff.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    return bool(np.all(near[mask]))


@pytest.fixture(scope="module")
def marbler(renderer):
    return Marbler(FIGURE6, renderer)


def test_bands_equal_the_single_shot_render(marbler, tmp_path):
    """3000 x 3000 PNG in bands of 700 rows = the one-shot render, up to the float32
    rounding of each band's shifted offset (a few edge pixels)."""
    full = marbler.render(None, None, (3000, 3000))[..., :3]
    dst = tmp_path / "big.png"
    render_still(None, marbler.recipe, dst, size=(3000, 3000), band_rows=700)
    got = read_rgb(dst)
    assert got.shape == full.shape
    differ = np.any(got != full, -1)
    assert differ.mean() < 2e-4, differ.sum()
    assert on_edge(full, differ)
    # progressive: one IDAT chunk per band (5 bands) plus the final flush
    data = dst.read_bytes()
    chunks, pos = [], 8
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        chunks.append(data[pos + 4 : pos + 8])
        pos += 12 + n
    assert chunks.count(b"IDAT") >= 5 and chunks[-1] == b"IEND"


@pytest.mark.parametrize("fmt", [".png", ".tif"])
@pytest.mark.parametrize("channels", [3, 4])
def test_stream_writers_round_trip(tmp_path, fmt, channels):
    tifffile = pytest.importorskip("tifffile")

    rng = np.random.default_rng(1)
    img = rng.integers(0, 256, (301, 97, 4)).astype(np.uint8)
    img[:100] = 9  # flat rows (the Up filter's zeros)
    dst = tmp_path / f"x{fmt}"
    write_bands(dst, fmt, 97, 301, channels, (img[i : i + 64] for i in range(0, 301, 64)))
    if fmt == ".png":
        got = cv2.imread(str(dst), cv2.IMREAD_UNCHANGED)
        got = got[..., [2, 1, 0, 3][:channels]]
    else:
        got = tifffile.imread(dst)
    assert np.array_equal(got, img[..., :channels])


def test_tiff_in_bands(marbler, tmp_path):
    tifffile = pytest.importorskip("tifffile")

    full = marbler.render(None, None, (640, 480))[..., :3]
    dst = tmp_path / "b.tif"
    render_still(None, marbler.recipe, dst, size=(640, 480), band_rows=100)
    got = tifffile.imread(dst)
    differ = np.any(got != full, -1)
    assert differ.mean() < 1e-3 and on_edge(full, differ)


def test_view_is_an_exact_zoom(marbler):
    """A 50 x 50 window at 200 x 200 = the same window cut from a 4x render."""
    big = marbler.render(None, None, (4096, 4096))[..., :3]
    zoom = marbler.render(None, None, (200, 200), view=(400.0, 500.0, 50.0, 50.0))[..., :3]
    crop = big[2000:2200, 1600:1800]
    differ = np.any(zoom != crop, -1)
    assert differ.mean() < 2e-3 and on_edge(crop, differ)
    # and the whole canvas as a view is the default render
    same = marbler.render(None, None, (256, 256), view=(0.0, 0.0, 1024.0, 1024.0))
    assert np.array_equal(same, marbler.render(None, None, (256, 256)))


def test_cli_view(cli, tmp_path):
    from pathlib import Path

    recipe = Path(FIGURE6).resolve()
    res = cli("--ops", recipe, "-o", "z.png", "--view", "400,500,50,50", "--size", "64x64", "-q")
    assert res.returncode == 0, res.stderr
    assert read_rgb(tmp_path / "z.png").shape == (64, 64, 3)
    for bad in ("1,2,3", "0,0,0,10", "a,b,c,d", "0,0,inf,1", "0,0,-5,5"):
        res = cli("--ops", recipe, "-o", "bad.png", f"--view={bad}")
        assert res.returncode == 2, (bad, res.stderr)
        assert res.stderr.startswith("marblevideo: --view") and res.stderr.count("\n") == 1
        assert not (tmp_path / "bad.png").exists()
