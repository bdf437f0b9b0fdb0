"""UV passes: the design evaluated exactly at (u * W, (1 - v) * H), AA through the
pass's screen-space derivatives; v = 0 at the bottom (Blender)."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers import ROOT, identity_pass
from recipes import blank_design

from marblevideo.outputs.uv import read_uv, render_uv
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")


def write_png16(path: Path, u: np.ndarray, v: np.ndarray, alpha: np.ndarray | None = None):
    rgba = np.zeros(u.shape + (4,), np.uint16)
    rgba[..., 0] = np.round(np.clip(u, 0, 1) * 65535)
    rgba[..., 1] = np.round(np.clip(v, 0, 1) * 65535)
    rgba[..., 3] = 65535 if alpha is None else alpha
    cv2.imwrite(str(path), cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGRA))


@pytest.mark.parametrize("aa", ["rgss", "quincunx", "none"])
def test_identity_pass_equals_a_plain_render(aa):
    recipe = blank_design(2)
    spec = recipe.at(recipe.end_time())
    spec = type(spec)(spec.ops, spec.background, aa, spec.edges, spec.canvas)
    w, h = 160, 120  # canvas 320 x 240 at half size
    u, v = identity_pass(w, h)
    got = render_uv(spec, u, v, np.ones((h, w), bool))
    want = reference_render(spec, geometry(spec.canvas, (w, h)))
    assert np.abs(got.astype(int) - want).max() <= 1


def test_sixteen_bit_png_pass(tmp_path):
    recipe = blank_design(4)
    spec = recipe.at(recipe.end_time())
    w, h = 160, 120
    u, v = identity_pass(w, h)
    alpha = np.full((h, w), 65535, np.uint16)
    alpha[:, :10] = 0  # no surface there
    write_png16(tmp_path / "uv.png", u, v, alpha)
    u2, v2, surface = read_uv(tmp_path / "uv.png")
    assert np.abs(u2 - u).max() < 1e-5 and not surface[:, :10].any() and surface[:, 10:].all()
    got = render_uv(spec, u2, v2, surface)
    want = reference_render(spec, geometry(spec.canvas, (w, h)))
    same = np.all(got[:, 10:] == want[:, 10:], -1)
    assert same.mean() > 0.995
    assert (got[:, :10, 3] == 0).all()  # transparent where there is no surface


def test_v_zero_is_the_bottom():
    """A drop near the canvas top shows where v is near 1."""
    from marblevideo.recipe import parse_recipe

    recipe = parse_recipe({"canvas": [100, 100], "background": "#ffffff", "ops": [
        {"type": "drop", "center": [50, 10], "radius": 8, "color": "#ff0000"}]})  # fmt: skip
    spec = recipe.at(0)
    u = np.array([[0.5, 0.5]])
    v = np.array([[0.9, 0.1]])  # canvas y = 10 and 90
    out = render_uv(spec, u, v, np.ones((1, 2), bool))
    assert tuple(out[0, 0, :3]) == (255, 0, 0) and tuple(out[0, 1, :3]) == (255, 255, 255)


def test_out_of_range_uv_is_no_surface(tmp_path):
    pytest.importorskip("OpenEXR", reason="EXR passes are read through the OpenEXR package")
    import OpenEXR

    u, v = identity_pass(32, 16)
    u[0, 0], v[0, 1], u[0, 2] = 1.5, -0.2, np.nan
    rgb = np.stack([u, v, np.zeros_like(u)], -1).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(header, {"RGB": rgb}).write(str(tmp_path / "uv.exr"))
    u2, v2, surface = read_uv(tmp_path / "uv.exr")
    assert not surface[0, :3].any() and surface[0, 3:].all() and surface[1:].all()
    assert np.abs(u2[1:] - u[1:]).max() < 1e-6


def test_cli_sphere_sample(cli, tmp_path):
    recipe = ROOT / "samples" / "figure6.json"
    uv = ROOT / "samples" / "sphere-uv.png"
    res = cli("--ops", recipe, "--uv", uv, "-o", "s.png", "-q")
    assert res.returncode == 0, res.stderr
    out = cv2.imread(str(tmp_path / "s.png"), cv2.IMREAD_UNCHANGED)
    assert out.shape == (256, 256, 4)
    assert out[0, 0, 3] == 0 and out[128, 128, 3] == 255
    assert len(np.unique(out[100:156, 100:156].reshape(-1, 4), axis=0)) > 5


def test_cli_uv_errors(cli, tmp_path):
    recipe = tmp_path / "r.json"
    recipe.write_text(json.dumps({"canvas": [10, 10], "ops": []}))
    grey = tmp_path / "grey.png"
    cv2.imwrite(str(grey), np.zeros((4, 4), np.uint8))
    for args, needle in [
        (("--uv", "missing.png"), "no such file"),
        (("--uv", recipe), "expected a .png"),
        (("--uv", grey), "colour channels"),
        (("--uv", grey, "--size", "5x5"), "--uv"),
    ]:
        res = cli("--ops", recipe, "-o", "o.png", *args)
        assert res.returncode == 2, (args, res.stderr)
        assert needle in res.stderr and res.stderr.count("\n") == 1
        assert not (tmp_path / "o.png").exists()
