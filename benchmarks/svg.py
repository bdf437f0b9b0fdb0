"""The svg part: SVG export of the bundled blank-sheet samples against the
raster renderer, and Figure 6 by size and tolerance."""

from __future__ import annotations

import time

import cv2
import numpy as np

from marblevideo.opencl.renderer import Renderer
from marblevideo.recipe.frame import geometry

from .common import ROOT

#: the bundled blank-sheet samples the svg part measures
SVG_SAMPLES = ("figure6", "nonpareil", "bouquet", "chevron", "spanish-wave", "stone-sprays")


def raster_svg(svg: str, size: tuple[int, int], k: int = 1) -> np.ndarray:
    """``svg`` rasterized by cairosvg at ``size`` (RGB); by area when ``k`` > 1
    (at k times the size, then reduced)."""
    import cairosvg

    png = cairosvg.svg2png(
        bytestring=svg.encode(), output_width=size[0] * k, output_height=size[1] * k
    )
    bgr = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
    return cv2.resize(rgb, size, interpolation=cv2.INTER_AREA) if k > 1 else rgb


def within(a: np.ndarray, b: np.ndarray, levels: int = 24) -> float:
    """% of pixels whose RGB channels are all within ``levels`` of ``b``'s."""
    d = np.abs(a[..., :3].astype(int) - b[..., :3].astype(int)).max(axis=-1)
    return 100 * float((d <= levels).mean())


def svg_part(device: str | None) -> None:
    """SVG export of every bundled blank-sheet sample: time, vertices and size at
    the default tolerance, and fidelity when zoomed, beside the raster renderer's
    own RGSS; then Figure 6 at 1024 px and at 4096 px at three tolerances."""
    import dataclasses

    from marblevideo.limits import DEFAULT_TOLERANCE
    from marblevideo.outputs.svg import design_svg
    from marblevideo.recipe import load_recipe

    renderer = Renderer(device)
    print(f"\n## SVG export at the default tolerance ({DEFAULT_TOLERANCE} px), raster on "
          f"{renderer.info.name}")  # fmt: skip
    print("Each sample's SVG at its canvas size, rasterized by cairosvg at 2x and 4x, against the")
    print("16-sample (grid4) raster render there: % of pixels within 24 levels, rasterized by area")
    print("(4x4 supersampled: the outlines) / directly (what a viewer shows), beside the raster")
    print("renderer's own RGSS against grid4 (the baseline: its antialiasing of the same design).")
    print("| sample | size | time | vertices (refined) | SVG | 2x: area / direct / RGSS "
          "| 4x: area / direct / RGSS |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for name in SVG_SAMPLES:
        recipe = load_recipe(ROOT / "samples" / f"{name}.json")
        spec = recipe.at(recipe.end_time())
        base = tuple(int(v) for v in spec.canvas)
        t = time.perf_counter()
        svg, stats = design_svg(spec, base)
        took = time.perf_counter() - t
        cells = []
        for scale in (2, 4):
            size = (base[0] * scale, base[1] * scale)
            geom = geometry(spec.canvas, size)
            grid4 = renderer.render(dataclasses.replace(spec, antialias="grid4"), geom)
            rgss = renderer.render(dataclasses.replace(spec, antialias="rgss"), geom)
            cells.append(
                f"{within(raster_svg(svg, size, 4), grid4):.2f} / "
                f"{within(raster_svg(svg, size), grid4):.2f} / {within(rgss, grid4):.2f}"
            )
        row = [f"{base[0]}x{base[1]}", f"{took:.1f} s"]
        row += [f"{stats.vertices} ({stats.refined_vertices})", f"{stats.bytes / 1024:.0f} KiB"]
        print(f"| {name} | " + " | ".join(row + cells) + " |", flush=True)
    figure6_sizes()


def figure6_sizes() -> None:
    """Figure 6 at 1024 and 4096 px by tolerance: time, vertices, size."""
    from marblevideo.limits import DEFAULT_TOLERANCE
    from marblevideo.outputs.svg import design_svg
    from marblevideo.recipe import load_recipe

    print("\nFigure 6 (samples/figure6.json), time and vertices by size and tolerance:")
    print("| size | tolerance | time | vertices (refined) | SVG |")
    print("|---|---|---|---|---|")
    recipe = load_recipe(ROOT / "samples" / "figure6.json")
    spec = recipe.at(recipe.end_time())
    for side, tol in ((1024, 0.5), (1024, DEFAULT_TOLERANCE), (4096, DEFAULT_TOLERANCE),
                      (4096, DEFAULT_TOLERANCE / 2)):  # fmt: skip
        t = time.perf_counter()
        _, stats = design_svg(spec, (side, side), tol)
        took = time.perf_counter() - t
        row = [f"{side} px", f"{tol:g} px", f"{took:.1f} s"]
        row += [f"{stats.vertices} ({stats.refined_vertices})", f"{stats.bytes / 1024:.0f} KiB"]
        print("| " + " | ".join(row) + " |", flush=True)
