"""SVG export: the vector design, rasterized by an independent renderer (cairosvg),
agrees with the OpenCL raster renderer; simplification stays within tolerance."""

from __future__ import annotations

import math

import numpy as np
import pytest
from svg_raster import agreement, rasterize
from tolerances import SVG_SHARE

from marblevideo.outputs.svg import design_svg, simplify_closed
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

cairosvg = pytest.importorskip("cairosvg", reason="cairosvg (test extra) rasterizes the SVG")


def blank_design(seed: int, w: float = 320, h: float = 240):
    """Seeded blank-sheet design: drops (and a spray) then combs, a wave and a vortex."""
    rng = np.random.default_rng(seed)
    size = min(w, h)

    def pt():
        return [float(rng.uniform(0, w)), float(rng.uniform(0, h))]

    def color():
        return [int(c) for c in rng.integers(0, 256, 3)]

    ops = [
        {"type": "drop", "center": pt(), "radius": float(rng.uniform(0.05, 0.2) * size),
         "color": color()}
        for _ in range(int(rng.integers(6, 12)))
    ]  # fmt: skip
    ops.append({"type": "spray", "center": pt(), "radius": 0.05 * size, "color": color()})
    for kind in rng.permutation(["comb", "comb", "wave", "vortex"]):
        if kind == "comb":
            op = {"point": pt(), "angle": float(rng.uniform(0, 360)),
                  "spacing": float(rng.uniform(0.15, 0.4) * size),
                  "alpha": float(rng.uniform(-0.15, 0.15) * size),
                  "lambda": float(rng.uniform(0.03, 0.1) * size)}  # fmt: skip
        elif kind == "wave":
            op = {"amplitude": float(rng.uniform(-0.05, 0.05) * size),
                  "wavelength": float(rng.uniform(0.3, 1) * size),
                  "phase": float(rng.uniform(0, 360)),
                  "angle": float(rng.uniform(0, 360))}  # fmt: skip
        else:
            op = {"center": pt(), "alpha": float(rng.uniform(-0.3, 0.3) * size),
                  "lambda": float(rng.uniform(0.1, 0.3) * size)}  # fmt: skip
        ops.append({"type": str(kind), **op})
    return parse_recipe({"canvas": [w, h], "background": color(), "ops": ops})


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_svg_agrees_with_the_raster_renderer(renderer, seed):
    recipe = blank_design(seed)
    spec = recipe.at(recipe.end_time())
    size = (640, 480)  # 2x the canvas
    svg, stats = design_svg(spec, size)
    assert stats.shapes == len(spec.ops) - 4 and not stats.capped
    assert stats.vertices < stats.refined_vertices
    raster = renderer.render(spec, geometry(spec.canvas, size))
    assert agreement(rasterize(svg, size), raster) >= SVG_SHARE


def test_later_ops_move_earlier_ink(renderer):
    """Without the forward maps of later ops the outlines would be the plain circles;
    the agreement test must see the difference (it is able to fail)."""
    recipe = blank_design(7)
    spec = recipe.at(recipe.end_time())
    size = (640, 480)
    raster = renderer.render(spec, geometry(spec.canvas, size))
    svg, _ = design_svg(spec, size)
    undeformed = type(spec)(spec.ops[:-4], spec.background, spec.antialias, spec.edges,
                            spec.canvas)  # fmt: skip
    plain, _ = design_svg(undeformed, size)
    assert agreement(rasterize(svg, size), raster) >= SVG_SHARE
    assert agreement(rasterize(plain, size), raster) < 0.95


def test_a_later_drop_pushes_earlier_ink_outward():
    """Concentric drops r1 then r2: the first outline becomes the circle of radius
    sqrt(r1^2 + r2^2) (area preserved), within the tolerance."""
    recipe = parse_recipe({"canvas": [400, 400], "ops": [
        {"type": "drop", "center": [200, 200], "radius": 50, "color": "#ff0000"},
        {"type": "drop", "center": [200, 200], "radius": 80, "color": "#0000ff"},
    ]})  # fmt: skip
    svg, stats = design_svg(recipe.at(0), (400, 400), tolerance=0.5)
    first = svg.split("<path")[1]
    coords = first[first.index('d="M') + 4 : first.index("Z")].replace("L", " ").split()
    pts = np.array([[float(v) for v in c.split(",")] for c in coords])
    radius = np.hypot(pts[:, 0] - 200, pts[:, 1] - 200)
    assert np.allclose(radius, math.hypot(50, 80), atol=0.05)
    assert stats.shapes == 2 and len(pts) > 16


def test_simplification_stays_within_tolerance():
    rng = np.random.default_rng(5)
    t = np.linspace(0, 2 * math.pi, 20000, endpoint=False)
    r = 100 + 10 * np.sin(7 * t) + rng.normal(0, 0.01, t.size)
    pts = np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
    tol = 0.2
    kept = simplify_closed(pts, tol)
    assert 50 < len(kept) < 2000
    # distance of every original vertex to the kept closed outline
    a = kept
    b = np.roll(kept, -1, axis=0)
    ab = b - a
    d = np.full(len(pts), np.inf)
    for i in range(len(a)):
        q = pts - a[i]
        s = np.clip((q @ ab[i]) / (ab[i] @ ab[i]), 0, 1)
        d = np.minimum(d, np.hypot(*(q - s[:, None] * ab[i]).T))
    assert d.max() <= tol + 1e-9


def test_refinement_guard_notes_the_cap(monkeypatch):
    import marblevideo.outputs.svg as vector

    monkeypatch.setattr(vector, "MAX_VERTICES", 2000)
    recipe = blank_design(1)
    _, stats = design_svg(recipe.at(recipe.end_time()), (640, 480), tolerance=0.05)
    assert stats.capped and "note" in stats.summary()


def test_cli_svg(cli, tmp_path):
    import json

    recipe = tmp_path / "d.json"
    doc = {"canvas": [200, 100], "ops": [
        {"type": "drop", "center": [100, 50], "radius": 30, "color": "#ff0000"},
        {"type": "comb", "point": [0, 0], "angle": 0, "spacing": 20, "alpha": 15, "lambda": 4},
    ]}  # fmt: skip
    recipe.write_text(json.dumps(doc))
    res = cli("--ops", recipe, "-o", "d.svg", "--size", "400x200", "--tolerance", "0.25")
    assert res.returncode == 0, res.stderr
    assert "vertices" in res.stderr and "KiB" in res.stderr
    text = (tmp_path / "d.svg").read_text()
    assert 'width="400" height="200" viewBox="0 0 200 100"' in text
    assert text.count("<path") == 1
    (tmp_path / "in.png").write_bytes(b"")
    for args, needle in [
        (("in.png", "--ops", recipe, "-o", "x.svg"), "cannot be vectorized"),
        (("--ops", recipe, "-o", "x.svg", "--tolerance", "0"), "--tolerance"),
        (("--ops", recipe, "-o", "x.svg", "--tolerance", "nan"), "--tolerance"),
    ]:
        res = cli(*args)
        assert res.returncode == 2 and needle in res.stderr
        assert len(res.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "x.svg").exists()
