"""The ``strokes`` part of the benchmarks: free-hand strokes against their
baselines, in one run on one renderer.

- the ``tulip`` preset at 1024x768 with RGSS (the bar: under 1 s), adaptive
  (the renderer's default on a blank sheet) and the full pattern, beside the
  ``figure6`` preset at the same size;
- one stroke of n steps against n ``circle`` ops (radius w/2 at the steps'
  centres, as many rotations) over the same drops (the bar: no slower);
- the host's packing of a 200000-step stroke per frame: static (laid out once,
  cached) and travelling (its acting steps packed afresh every frame);
- a stroke drawn in time (``times``, revision 4) against the same stroke as
  revision 3 travelling with ``start``/``end`` at the same speed, frame by frame
  across the gesture (recipe at t, packing and render), the two timed in
  alternating rounds (the bar: no slower), and the packing of each at 200000 steps.

    python -m benchmarks strokes
"""

from __future__ import annotations

import itertools
import json
from functools import partial

import numpy as np

from marblevideo import load_recipe, samples_path
from marblevideo.opencl.program import pack_params
from marblevideo.opencl.renderer import Renderer
from marblevideo.ops.stroke import acting_steps, layout
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

from . import common
from .motion_clip import texture

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
    timed_against_revision3(full)


def _gesture(width: float, drawn: bool, points: list, duration: float) -> dict:
    """A stroke across the drops, drawn at constant speed over ``duration`` s: with
    ``times`` (revision 4) or with ``start``/``end`` (revision 3)."""
    stroke = {"type": "stroke", "points": points, "width": width, "drag": 1.2}
    if drawn:
        pts = np.asarray(points, float)
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
        stroke["times"] = (duration * arc / arc[-1]).tolist()
    else:
        stroke.update(start=0.0, end=duration)
    return {"canvas": [1024, 768], "antialias": "rgss", "ops": [*_drops(), stroke]}


def _paired(calls: dict, rounds: int, repeat: int) -> dict[str, tuple[float, float]]:
    """Each call's (best, median) over ``rounds`` alternating rounds of ``repeat``
    runs (order swapped every round): the medians of the rounds' medians."""
    got: dict[str, list] = {name: [] for name in calls}
    names = list(calls)
    for k in range(rounds):
        for name in names if k % 2 == 0 else names[::-1]:
            got[name].append(timings(calls[name], repeat=repeat, warmup=1))
    return {n: (min(b for b, _ in r), float(np.median([m for _, m in r]))) for n, r in got.items()}


def timed_against_revision3(full: Renderer) -> None:
    """The same stroke as a drawn gesture (times) and as revision 3 (start/end)."""
    print("\n## A stroke drawn in time against the same stroke as revision 3, 1024x768 over")
    print("24 drops, full RGSS: ms per frame (recipe at t, packing, render) over 12 frames")
    print("across the gesture, best / median of 4 alternating rounds")
    print("| width | revision 3 (start/end) | times (revision 4) | times / revision 3 |")
    print("|---|---|---|---|")
    points = [[60.0 + 9 * k, 380 - 130 * np.sin(k / 16)] for k in range(101)]
    moments = np.linspace(0.1, 2.0, 12)
    for width in (160.0, 40.0, 10.0):
        calls = {}
        for drawn in (False, True):
            recipe = parse_recipe(_gesture(width, drawn, points, 2.0), "bench.json")
            geom, frames = geometry(recipe.canvas, SIZE), itertools.cycle(moments)
            full.render(recipe.at(1.0), geom)  # the program built before timing
            calls[drawn] = lambda r=recipe, g=geom, f=frames: full.render(r.at(next(f)), g)
        got = _paired({"rev3": calls[False], "times": calls[True]}, rounds=4, repeat=12)
        ratio = got["times"][1] / got["rev3"][1]
        print(f"| {width:g} | {_ms(got['rev3'])} | {_ms(got['times'])} | {ratio:.2f} |")
    points = [[40.0 + 90 * k, 100.0 + 500 * (k % 2)] for k in range(11)]
    calls = {}
    for drawn in (False, True):
        doc = _gesture(0.21, drawn, points, 10.0)
        doc["ops"] = [{**doc["ops"][-1], "tines": [0, 8]}]
        recipe = parse_recipe({**doc, "canvas": [1000, 700]}, "bench.json")
        frames = itertools.cycle(np.linspace(5.0, 9.99, 100))
        calls[drawn] = lambda r=recipe, f=frames: pack_params(r.at(float(next(f))))
    got = _paired({"rev3": calls[False], "times": calls[True]}, rounds=4, repeat=7)
    print("\nPacking one stroke of about 200000 steps mid-gesture, ms per frame:")
    print(f"revision 3 {_ms(got['rev3'])}, times {_ms(got['times'])}", flush=True)


def motion_strokes(width: float = 140.0, points: int = 50, spacing: float = 19.0) -> list[dict]:
    """Six strokes as the motion analysis lays them on the six-disc clip
    (:mod:`benchmarks.motion_clip`): each follows its disc round its circle (radius
    90), ``points`` points ``spacing`` apart (about 930 canvas units, 26 steps of a
    140-wide stroke), drawn at 30 points a second, ``drag`` 1.5, healing far later."""
    from .motion_clip import RADIUS

    size, out = (1280, 720), []
    for k in range(6):
        gx, gy = size[0] * (1 + 2 * (k % 3)) / 6, size[1] * (1 + 2 * (k // 3)) / 4
        turn = (-1) ** k * spacing / RADIUS
        path = [
            [
                round(gx + RADIUS * np.cos(k + turn * j), 2),
                round(gy + RADIUS * np.sin(k + turn * j), 2),
            ]
            for j in range(points)
        ]
        times = [j / 30 for j in range(points)]
        out.append({"type": "stroke", "points": path, "times": times, "width": width,
                    "drag": 1.5, "heal": [100.0, 102.5]})  # fmt: skip
    return out


def motion_render(device: str | None, repeat: int = 11) -> None:
    """A 1280x720 frame of the ``dance`` preset (two waves) alone and with six motion
    strokes (:func:`motion_strokes`), in process, loop walk (as the live session
    renders), exact walk and lattice allowed."""
    doc = json.loads(samples_path("dance.json").read_text())
    doc = {k: v for k, v in doc.items() if k not in ("motion", "$schema")}
    renderer = Renderer(device, loop_walk=True, reuse_maps=False)
    ground = texture(1280, 720, 1)
    print("\n## The dance preset at 1280x720 with six motion strokes, loop walk, in process")
    print(f"ms per frame, best / median of {repeat}")
    print("| a frame of | exact walk | lattice allowed | steps |")
    print("|---|---|---|---|")
    for name, extra in (("two waves", []), ("two waves and six motion strokes", motion_strokes())):
        recipe = parse_recipe({**doc, "ops": [*doc["ops"], *extra]}, "bench.json")
        spec, geom = recipe.at(5.0), geometry(recipe.canvas, (1280, 720))
        frame = np.empty((720, 1280, 4), np.uint8)
        render = partial(renderer.render, spec, geom, ground, out=frame)
        cells = [_ms(timings(partial(render, lattice=lat), repeat=repeat)) for lat in (False, True)]
        steps = sum(len(acting_steps(op.values)[2]) for op in spec.ops if op.type == "stroke")
        print(f"| {name} | {cells[0]} | {cells[1]} | {steps} |", flush=True)


if __name__ == "__main__":
    import sys

    motion_render(None, int(sys.argv[1]) if len(sys.argv) > 1 else 11)
