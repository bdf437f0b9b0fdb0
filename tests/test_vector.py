"""SVG export: the vector design, rasterized by an independent renderer (cairosvg),
agrees with the OpenCL raster renderer; simplification stays within tolerance."""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np
import pytest
from recipes import blank_design
from svg_raster import agreement, path_points, rasterize
from tolerances import SVG_SHARE, ZOOM_LEVELS, ZOOM_SHARE, ZOOM_SUPERSAMPLE

from marblevideo.outputs.svg import design_svg, simplify_closed
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

pytestmark = pytest.mark.tier("integration")

cairosvg = pytest.importorskip("cairosvg", reason="cairosvg (test extra) rasterizes the SVG")


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
    pts = path_points(svg, 0)
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
    import marblevideo.outputs.outlines as outlines

    monkeypatch.setattr(outlines, "MAX_VERTICES", 2000)
    recipe = blank_design(1)
    _, stats = design_svg(recipe.at(recipe.end_time()), (640, 480), tolerance=0.05)
    assert stats.capped and "note" in stats.summary()


def _combed_drop(folder: Path) -> Path:
    """A 200 x 100 recipe file: a drop, then a comb through it."""
    import json

    recipe = folder / "d.json"
    doc = {"canvas": [200, 100], "ops": [
        {"type": "drop", "center": [100, 50], "radius": 30, "color": "#ff0000"},
        {"type": "comb", "point": [0, 0], "angle": 0, "spacing": 20, "alpha": 15, "lambda": 4},
    ]}  # fmt: skip
    recipe.write_text(json.dumps(doc))
    return recipe


def test_cli_svg(cli, tmp_path):
    recipe = _combed_drop(tmp_path)
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


def strong_design(seed: int, w: float = 240, h: float = 180):
    """Drops pulled into thin filaments: strong vortices, combs and a rake."""
    rng = np.random.default_rng(seed)
    ops = [
        {"type": "drop", "center": [float(rng.uniform(0, w)), float(rng.uniform(0, h))],
         "radius": float(rng.uniform(15, 40)), "color": [int(c) for c in rng.integers(0, 256, 3)]}
        for _ in range(10)
    ]  # fmt: skip
    ops += [
        {"type": "comb", "point": [0, 0], "angle": float(rng.uniform(0, 180)), "spacing": 30,
         "alpha": 25, "lambda": 3},
        {"type": "vortex", "center": [w / 2, h / 2], "alpha": 400, "lambda": 30},
        {"type": "rake", "point": [w / 2, h / 2], "angle": 90, "alpha": 30, "falloff": 4,
         "spacing": 24, "count": 12},
        {"type": "vortex", "center": [w / 3, h / 3], "alpha": -250, "lambda": 20},
    ]  # fmt: skip
    return parse_recipe({"canvas": [w, h], "background": "#f1faee", "ops": ops}, "strong.json")


SAMPLES = Path(__file__).resolve().parent.parent / "samples"


def _blank_sheet(path: Path) -> bool:
    """Whether a bundled file is a recipe with ink (drops, sprays, layouts)."""
    from marblevideo.ops import op_def
    from marblevideo.recipe import load_recipe

    if path.name == "recipe.schema.json":
        return False
    return any(op_def(op.type).ink for op in load_recipe(path).ops)


#: The bundled blank-sheet designs: every one is checked.
BLANK_SHEET = sorted(p.stem for p in SAMPLES.glob("*.json") if _blank_sheet(p))


@functools.cache
def _svg(name: str):
    """(frame spec, canvas size, SVG at that size and the default tolerance) of a
    bundled sample, or of ``strong<seed>``."""
    from marblevideo.recipe import load_recipe

    if name.startswith("strong"):
        recipe = strong_design(int(name[6:]))
    else:
        recipe = load_recipe(SAMPLES / f"{name}.json")
    spec = recipe.at(recipe.end_time())
    base = tuple(int(v) for v in spec.canvas)
    svg, stats = design_svg(spec, base)
    assert not stats.capped
    return spec, base, svg


#: The zooms the SVG is looked at.
ZOOMS = (2, 4)


@functools.lru_cache(maxsize=1)  # a design's zooms run one after the other
def _fine(name: str) -> np.ndarray:
    """The SVG of ``name`` rasterized by cairosvg at ZOOM_SUPERSAMPLE times the
    largest zoom: one rasterization (cairosvg's time is mostly its path parsing)
    averaged down for every zoom, ZOOM_SUPERSAMPLE or more points a pixel's side."""
    _, base, svg = _svg(name)
    k = max(ZOOMS) * ZOOM_SUPERSAMPLE
    return rasterize(svg, (base[0] * k, base[1] * k))


def _zoom(renderer, name: str, scale: int) -> tuple[float, float, float]:
    """The SVG of ``name`` rasterized at ``scale`` times its size against the
    16-sample raster render there: the share of pixels within ZOOM_LEVELS when
    rasterized supersampled (the outlines; :func:`_fine`, each pixel by area) and
    directly (what a viewer shows), and the share of the raster renderer's own
    4-sample RGSS (its antialiasing of the same design)."""
    import dataclasses

    import cv2

    spec, base, svg = _svg(name)
    size = (base[0] * scale, base[1] * scale)
    geom = geometry(spec.canvas, size)
    raster = renderer.render(dataclasses.replace(spec, antialias="grid4"), geom)
    rgss = renderer.render(dataclasses.replace(spec, antialias="rgss"), geom)
    return (
        agreement(cv2.resize(_fine(name), size, interpolation=cv2.INTER_AREA), raster, ZOOM_LEVELS),
        agreement(rasterize(svg, size), raster, ZOOM_LEVELS),
        agreement(rgss, raster, ZOOM_LEVELS),
    )


def test_every_blank_sheet_sample_is_checked():
    assert {"figure6", "nonpareil", "bouquet", "chevron", "stone-sprays"} <= set(BLANK_SHEET)


@pytest.mark.parametrize("scale", ZOOMS)
def test_figure6_shows_every_filament_when_zoomed(renderer, scale):
    """Figure 6's SVG zoomed 2x and 4x keeps its thin filaments: rasterized by
    cairo directly and supersampled, it matches the raster render there."""
    outlines, direct, _ = _zoom(renderer, "figure6", scale)
    assert direct >= ZOOM_SHARE and outlines >= ZOOM_SHARE


@pytest.mark.parametrize("scale", ZOOMS)
@pytest.mark.parametrize(
    "name", [n for n in BLANK_SHEET if n != "figure6"] + ["strong0", "strong1", "strong2"]
)
def test_svg_stays_faithful_when_zoomed(renderer, name, scale):
    """Outlines right at 2x and 4x; shown directly, no further from the 16-sample
    render than the raster renderer's own RGSS is (stripes under a pixel wide
    are where both differ)."""
    outlines, direct, rgss = _zoom(renderer, name, scale)
    assert outlines >= ZOOM_SHARE, (outlines, direct, rgss)
    assert direct >= rgss, (outlines, direct, rgss)


def test_every_outline_lies_within_the_tolerance_of_the_true_image():
    """Each written edge against the exact image of the arc it stands for, sampled
    16 times as densely as the refined outline: every true point within the
    tolerance of its edge (the guarantee; not merely of the nearest edge)."""
    from marblevideo.outputs.outlines import VectorStats, push_forward, refine_outlines
    from marblevideo.outputs.svg import SIMPLIFIED, simplified_indices

    recipe = strong_design(5, 120, 90)
    spec = recipe.at(recipe.end_time())
    tol = 0.5  # canvas units (the outlines of a 120 x 90 output at 0.5 px)
    outlines = refine_outlines(spec, tol, VectorStats())
    assert len(outlines) == 10
    for outline in outlines:
        points = np.stack([outline.x, outline.y], axis=1)
        kept = simplified_indices(points, SIMPLIFIED * tol)
        edges = np.append(outline.theta, 2 * math.pi)
        theta = (edges[:-1, None] + np.diff(edges)[:, None] * np.arange(16) / 16).ravel()
        cx, cy = spec.ops[outline.op]["center"]
        r = spec.ops[outline.op]["radius"]
        x, y = push_forward(spec, outline.op, cx + r * np.cos(theta), cy + r * np.sin(theta))
        # the written edge that stands for each sample's arc: kept[i] -> kept[i + 1]
        arc = np.searchsorted(outline.theta[kept], theta, side="right") - 1
        arc[arc < 0] = len(kept) - 1  # before the first kept vertex: the closing edge
        a = points[kept[arc]]
        b = points[kept[(arc + 1) % len(kept)]]
        ab = b - a
        q = np.stack([x, y], axis=1)
        t = np.clip(np.einsum("ij,ij->i", q - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
        off = np.hypot(*(q - a - t[:, None] * ab).T)
        assert off.max() <= tol, (outline.op, off.max())


def test_cli_pdf_is_a_vector_page(cli, tmp_path):
    import re
    import zlib

    recipe = _combed_drop(tmp_path)
    res = cli("--ops", recipe, "-o", "d.pdf", "--size", "400x200", "-y")
    assert res.returncode == 0, res.stderr
    data = (tmp_path / "d.pdf").read_bytes()
    assert data.startswith(b"%PDF") and b"/MediaBox [ 0 0 300 150 ]" in data  # 400 px at 96 dpi
    streams = [
        zlib.decompressobj().decompress(m.group(1))
        for m in re.finditer(rb"/FlateDecode[^>]*>>\s*stream\r?\n(.*?)endstream", data, re.S)
    ]
    ops = b"".join(streams)
    assert ops.count(b" l") > 50 and b" f" in ops  # lines and fills: vectors, no image
    assert b"/Subtype /Image" not in data
    res = cli("in.png", "--ops", recipe, "-o", "x.pdf")
    assert res.returncode == 2 and "cannot be vectorized" in res.stderr
    assert not (tmp_path / "x.pdf").exists()
