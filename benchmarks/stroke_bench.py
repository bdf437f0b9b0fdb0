"""The ``strokes`` part of the benchmarks: free-hand strokes against their
baselines, in one run on one renderer.

- the ``tulip`` preset at 1024x768 with RGSS (the bar: under 1 s), adaptive
  (the renderer's default on a blank sheet) and the full pattern, beside the
  ``figure6`` preset at the same size;
- one stroke of n steps against n ``circle`` ops (radius w/2 at the steps'
  centres, as many rotations) over the same drops (the bar: no slower);
- the host's packing of a 200000-step stroke per frame: static (laid out once,
  cached) and travelling (its acting steps packed afresh every frame).

    python -m benchmarks strokes
"""

from __future__ import annotations

from functools import partial

import numpy as np

from marblevideo import load_recipe
from marblevideo.opencl.program import pack_params
from marblevideo.opencl.renderer import Renderer
from marblevideo.ops.stroke import layout
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

from . import common

SIZE = (1024, 768)


#: the benchmarks' timer, at this part's counts (best and median of 11 after 2 warm-ups)
timings = partial(common.timings, repeat=11, warmup=2)


def _ms(pair: tuple[float, float]) -> str:
    return f"{pair[0] * 1e3:.0f} / {pair[1] * 1e3:.0f}"


def presets(adaptive: Renderer, full: Renderer) -> None:
    print(f"\n## Stroke presets at {SIZE[0]}x{SIZE[1]}, RGSS, ms per frame (best / median of 11)")
    print("| preset | ops | adaptive (default) | full pattern |")
    print("|---|---|---|---|")
    for name in ("tulip", "heart", "french-curl", "bird", "figure6"):
        recipe = load_recipe(name)
        spec, geom = recipe.at(recipe.end_time()), geometry(recipe.canvas, SIZE)
        frame = np.empty((SIZE[1], SIZE[0], 4), np.uint8)
        cells = [
            _ms(timings(lambda r=r, s=spec, g=geom, f=frame: r.render(s, g, out=f)))
            for r in (adaptive, full)
        ]
        print(f"| {name} | {len(recipe.ops)} | {cells[0]} | {cells[1]} |", flush=True)


def _drops() -> list[dict]:
    colors = ("#1d3557", "#e9c46a", "#b23a48", "#2a9d8f")
    return [
        {"type": "drop", "center": [150 + 100 * (k % 8), 200 + 150 * (k // 8)], "radius": 45,
         "color": colors[k % 4]}
        for k in range(24)
    ]  # fmt: skip


def stroke_against_circles(full: Renderer) -> None:
    """One stroke of n steps across the drops against n circle ops at its steps."""
    print("\n## One stroke of n steps against n circle ops, 1024x768 over 24 drops, full RGSS")
    print("ms per frame, best / median of 11")
    print("| n steps | stroke | n circles | circles / stroke |")
    print("|---|---|---|---|")
    for width in (160.0, 40.0, 10.0):
        stroke = {"type": "stroke", "points": [[60, 380], [500, 250], [960, 420]],
                  "width": width, "drag": 1.2}  # fmt: skip
        lay = layout((60.0, 380.0, 500.0, 250.0, 960.0, 420.0), width, (0.0,))
        circles = [
            {"type": "circle", "center": [float(c[0]), float(c[1])], "radius": width / 2,
             "alpha": 0.6 * lay.step, "lambda": width / 4}
            for c in lay.centres
        ]  # fmt: skip
        cells = []
        for ops in ([stroke], circles):
            doc = {"canvas": [1024, 768], "antialias": "rgss", "ops": [*_drops(), *ops]}
            recipe = parse_recipe(doc, "bench.json")
            spec, geom = recipe.at(0), geometry(recipe.canvas, SIZE)
            full.render(spec, geom)  # the program built before timing
            cells.append(timings(lambda s=spec, g=geom: full.render(s, g)))
        ratio = cells[1][1] / cells[0][1]
        print(f"| {lay.n} | {_ms(cells[0])} | {_ms(cells[1])} | {ratio:.1f}x |", flush=True)


def packing() -> None:
    """pack_params of a 200000-step stroke: static (cached) and travelling."""
    points = [[40.0 + 90 * k, 100.0 + 500 * (k % 2)] for k in range(11)]
    stroke = {"type": "stroke", "points": points, "width": 0.21, "tines": [0, 8]}
    doc = {"canvas": [1000, 700], "ops": [{**stroke, "start": 0, "end": 10}]}
    recipe = parse_recipe(doc, "bench.json")
    steps = layout(tuple(c for p in points for c in p), stroke["width"], (0.0, 8.0)).centres.shape[
        0
    ]
    static = timings(lambda: pack_params(recipe.at(10.0)), repeat=7)
    frames = iter(np.linspace(5.0, 9.99, 100))
    moving = timings(lambda: pack_params(recipe.at(float(next(frames)))), repeat=7)
    print(f"\n## Packing one stroke of {steps} steps (one op), ms per frame (best / median of 7)")
    print("| static (laid out once) | travelling (half to all its steps packed afresh) |")
    print("|---|---|")
    print(f"| {_ms(static)} | {_ms(moving)} |", flush=True)


def strokes_part(device: str | None) -> None:
    adaptive, full = Renderer(device), Renderer(device, adaptive=False)
    print(f"\n# strokes on {adaptive.info.name}")
    presets(adaptive, full)
    stroke_against_circles(full)
    packing()
