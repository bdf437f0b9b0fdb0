"""marblevideo benchmarks, each beside its baseline in the same run.

    python benchmarks/bench.py                 # everything below (several minutes)
    python benchmarks/bench.py table1 e2e numpy memory

- table1: the paper's Table 1 (frames per second of a blank-sheet design) for a
  12-op recipe in the spirit of its Figure 6 (6 drops, 4 combs, a wave, a
  vortex) at its five sizes and four AA columns; kernel time only (render +
  read back), adaptive and full-pattern sampling, beside the paper's GPU figures.
- e2e: marbling a 1280x720 clip (that recipe, RGSS) with libx264 veryfast crf 23,
  against a plain PyAV decode + encode of the same clip with the same settings
  (plain_transcode.py, as a script of its own and in-process); clips of 4 and 20
  seconds (--seconds), since the CLI's fixed start weighs less on a longer one;
  the animated recipe with the lattice (the default) and with --exact-walk.
- numpy: our renderer against the same recipe computed per frame with NumPy
  float32 inverse maps and cv2.remap (one remap per RGSS subsample).
- memory: peak RSS of the CLI marbling a 1080p clip of 10 s and of 10 minutes (--long).
- pst: a pst-marble-style design (rings, two rakes, a stir, a Lamb-Oseen vortex)
  at 1024x1024 in Table 1's columns, beside the 12-op row.
- svg: SVG export of every bundled blank-sheet sample (time, vertices, size,
  and agreement with the raster render at 2x and 4x, beside the raster's own
  RGSS), and Figure 6 at 1024 and 4096 px by tolerance.
- bullseye: 30 concentric drops and a comb walked with the drops as one run,
  against the same drops with centres 1/1000 px apart (which no run joins).
- bounds: on e2e's clip, what any sampling scheme can reach: the animated
  recipe with one sample per pixel (every pixel walked and gathered once), one
  keyed turn (a walk of next to nothing) with RGSS and with one sample, and the
  plain transcode of the marbled output (x264's cost for marbled pictures).
- series: the bundled samples with rakes and the pst design (rakes and a stir),
  evenly spaced tines and rings summed in closed form (four exponentials an op)
  against one exponential per term, in one program.
- busy: every blank-sheet sample halfway and at its end, the share of pixels
  adaptive sampling lists against its time and the full pattern's.
- animations: every frame of four sample animations at 960x640, the ops that
  have not started skipped by the walk against every op walked.
- cluster: a 720p clip (the e2e recipe, animated) rendered whole, in 4
  segments serially (plan, segments and join timed) and on a local Ray with
  1 and 2 workers (cluster_bench.py; needs the extra 'ray').
- lattice, live1080: the interpolated inverse map of animated frames against
  the exact walk, quality and time, and live at 1080p (lattice_bench.py).
- lanes: the vector width on this CPU: 16 against 8 lanes (and 4), for the code
  PoCL generates for this CPU and for an AVX2 CPU (POCL_KERNELLIB_NAME=avx2),
  each in a process of its own: a blank-sheet frame, a 720p frame over an input
  walked afresh and from reused maps, and a planar 720p frame.
- strokes: the stroke presets at 1024x768 (tulip under 1 s), one stroke of n
  steps against n circle ops, and the packing of a 200000-step stroke
  (stroke_bench.py).

Timings are medians; the machine is shared, so treat differences under 1.3x as noise.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import av
import cv2
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from plain_transcode import plain_transcode  # noqa: E402

from marblevideo.opencl.renderer import Renderer  # noqa: E402
from marblevideo.recipe import parse_recipe  # noqa: E402
from marblevideo.recipe.frame import geometry  # noqa: E402
from marblevideo.reference import inverse_walk  # noqa: E402

PAPER = {  # Table 1 of Lu et al. 2012: GeForce 8800GTS, frames per second
    (512, 512): (1560, 732, 250, 239),
    (1024, 512): (1265, 375, 125, 120),
    (1024, 768): (850, 246, 83, 80),
    (1024, 1024): (660, 189, 64, 61),
    (1280, 1024): (548, 156, 55, 53),
}
COLUMNS = ("none", "rgss", "checker4", "grid4")


def recipe12(antialias: str = "rgss") -> dict:
    """6 concentric drops, 4 combs (there and back, both directions), a wave, a vortex."""
    colors = ["#1d3557", "#e9c46a", "#b23a48", "#f4f1de", "#2a9d8f", "#e76f51"]
    ops = [{"type": "drop", "center": [512, 512], "radius": 190, "color": c} for c in colors]
    for angle, point in ((180, [0, 0]), (0, [0, 32]), (90, [0, 0]), (270, [32, 0])):
        ops.append(
            {
                "type": "comb",
                "point": point,
                "angle": angle,
                "spacing": 64,
                "alpha": 44,
                "lambda": 16,
            }
        )
    ops.append({"type": "wave", "amplitude": 26, "wavelength": 220, "phase": 0, "angle": 90})
    ops.append({"type": "vortex", "center": [512, 512], "alpha": 300, "lambda": 120})
    return {
        "marblevideo": 1,
        "canvas": [1024, 1024],
        "background": "#f3ead7",
        "antialias": antialias,
        "ops": ops,
    }


def timings(fn, repeat: int = 21, warmup: int = 3) -> tuple[float, float]:
    """(best, median) of ``repeat`` runs. On this shared VM the same render ran in
    two phases about 2x apart (as if one core were taken away at times), so both
    are reported: the best is what the kernel does, the median what a run met."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def median_time(fn, repeat: int = 21, warmup: int = 3) -> float:
    return timings(fn, repeat, warmup)[1]


def recipe_pst(antialias: str = "rgss") -> dict:
    """A pst-marble-style design: 8 rings, two rakes of 32 tines there and back, a
    stir of 8 rings, a Lamb-Oseen vortex (the revision-2 vocabulary)."""
    palette = ["#1d3557", "#e9c46a", "#b23a48", "#f4f1de", "#2a9d8f", "#264653"]
    return {
        "marblevideo": 1,
        "canvas": [1024, 1024],
        "background": "#f3ead7",
        "antialias": antialias,
        "ops": [
            {"type": "rings", "center": [512, 512], "width": 60, "count": 8, "colors": palette},
            {"type": "rake", "point": [512, 512], "angle": 90, "alpha": 60, "falloff": 8,
             "spacing": 32, "count": 32},
            {"type": "rake", "point": [528, 512], "angle": 270, "alpha": 60, "falloff": 8,
             "spacing": 32, "count": 32},
            {"type": "stir", "center": [512, 512], "radii": [60, -120, 180, -240, 300, -360,
             420, -480], "alpha": 40, "falloff": 20},
            {"type": "oseen", "center": [512, 512], "circulation": 3.0e4, "viscosity": 500,
             "time": 3},
        ],
    }  # fmt: skip


def kernel_cell(adaptive, full, data: dict, size: tuple[int, int], patterned: bool) -> str:
    """A Table 1 cell: the blank-sheet recipe ``data`` at ``size``, read back into
    one frame buffer, in fps "best / median of 21", and with an antialiasing
    pattern " [the full pattern's best]"."""
    recipe = parse_recipe(data, "table1.json")
    spec, geom = recipe.at(0), geometry(recipe.canvas, size)
    frame = np.empty((size[1], size[0], 4), np.uint8)
    best, med = timings(lambda: adaptive.render(spec, geom, out=frame))
    cell = f"{1 / best:.0f} / {1 / med:.0f}"
    if patterned:
        full_best, _ = timings(lambda: full.render(spec, geom, out=frame), repeat=11)
        cell += f" [{1 / full_best:.0f}]"
    return cell


def pst_row(device: str | None) -> None:
    """The pst-style design at 1024x1024 in Table 1's columns, beside the 12-op row."""
    adaptive, full = Renderer(device), Renderer(device, adaptive=False)
    print(f"\n## A pst-style design (revision 2 ops), kernel fps on {adaptive.info.name}")
    print("Each cell: ours best / median of 21 [full pattern, best]")
    print("| recipe at 1024x1024 | " + " | ".join(COLUMNS) + " |")
    print("|---|" + "---|" * len(COLUMNS))
    for name, make in (("12 ops (Table 1)", recipe12), ("pst-style", recipe_pst)):
        cells = []
        for col in COLUMNS:
            cells.append(kernel_cell(adaptive, full, make(col), (1024, 1024), col != "none"))
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)


def bullseye(device: str | None, drops: int = 30) -> None:
    """See the module: ms per 1024x1024 blank-sheet frame, full RGSS, both
    recipes interleaved (median of 21), so that both see the VM's same phases."""
    colors = ["#1d3557", "#e9c46a", "#b23a48", "#f4f1de"]

    def spec(apart: float):
        ops = [
            {
                "type": "drop",
                "center": [512 + apart * (k % 2), 512],
                "radius": 60 + 3 * k,
                "color": colors[k % 4],
            }
            for k in range(drops)
        ]
        ops.append(
            {
                "type": "comb",
                "point": [0, 0],
                "angle": 90,
                "spacing": 64,
                "alpha": 40,
                "lambda": 16,
            }
        )
        data = {"marblevideo": 1, "canvas": [1024, 1024], "antialias": "rgss", "ops": ops}
        return parse_recipe(data, "bullseye.json").at(0)

    renderer = Renderer(device, adaptive=False)
    geom = geometry((1024, 1024), (1024, 1024))
    specs = {"run": spec(0.0), "apart": spec(1e-3)}
    times: dict[str, list[float]] = {name: [] for name in specs}
    for _ in range(21):
        for name, one in specs.items():
            began = time.perf_counter()
            renderer.render(one, geom)
            times[name].append(time.perf_counter() - began)
    run, apart = (statistics.median(times[k]) * 1e3 for k in ("run", "apart"))
    print(f"\n## {drops} concentric drops and a comb, 1024x1024 blank sheet, full RGSS")
    print(
        f"drops walked as one run: {run:.1f} ms; one by one (centres 0.001 px apart): "
        f"{apart:.1f} ms; {apart / run:.2f}x"
    )


def series(device: str | None) -> None:
    """See the module: the bundled samples with rakes and the pst design (rakes
    and a stir) at 960x640, ms per frame (median of 15, interleaved), evenly
    spaced tines and rings summed in closed form against term by term (the same
    program; only the packed data differ)."""
    import json

    from marblevideo.ops import series as sums
    from marblevideo.ops import shear

    samples = ROOT / "samples"
    designs = {
        name: json.loads((samples / f"{name}.json").read_text())
        for name in ("nonpareil", "bouquet", "chevron", "spanish-wave")
    }
    designs["pst (1024 canvas)"] = recipe_pst()
    print("\n## Rakes and stirs: 960x640, ms per frame, median of 15")
    print("| design | terms | pattern | term by term | closed form | speed-up |")
    print("|---|---|---|---|---|---|")
    for name, data in designs.items():
        recipe = parse_recipe(data, name)
        spec = recipe.at(recipe.end_time())
        terms = sum(
            len(shear.rake_offsets(op.values)) if op.type == "rake" else len(op.values["radii"])
            for op in spec.ops
            if op.type in ("rake", "stir")
        )
        geom = geometry(recipe.canvas, (960, 640))
        renderers = {
            "adaptive": Renderer(device, adaptive=True),
            "full": Renderer(device, adaptive=False),
        }
        for label, renderer in renderers.items():
            times: dict[str, list[float]] = {"terms": [], "closed": []}
            for k in range(17):
                for mode in times:
                    sums.SERIES_MIN = 10**9 if mode == "terms" else 4
                    began = time.perf_counter()
                    renderer.render(spec, geom)
                    if k >= 2:  # the first two warm up
                        times[mode].append(time.perf_counter() - began)
            sums.SERIES_MIN = 4
            loop, closed = (statistics.median(times[m]) * 1e3 for m in ("terms", "closed"))
            cells = f"{loop:.1f} | {closed:.1f} | {loop / closed:.2f}x"
            print(f"| {name} | {terms} | {label} | {cells} |", flush=True)


def animations(device: str | None) -> None:
    """See the module: every frame of sample animations at 960x640 (30 fps,
    blank sheet), ms per frame (mean over the animation, best of two passes),
    in one process: every op walked and adaptive sampling on every frame (as
    before session 12), the ops not started skipped (OpDef.still), and that
    with the default renderer, which takes the full pattern after a busy frame."""
    import json

    from marblevideo.ops.base import OpDef

    still = OpDef.still
    samples = ROOT / "samples"
    print("\n## Animations: every frame at 960x640, ms per frame (best of 2 passes)")
    print("| sample | frames | every op, adaptive | not started skipped | and busy frames full |")
    print("|---|---|---|---|---|")
    for name in ("figure6", "nonpareil", "bouquet", "chevron"):
        recipe = parse_recipe(json.loads((samples / f"{name}.json").read_text()), name)
        geom = geometry(recipe.canvas, (960, 640))
        n = int(recipe.end_time() * 30) + 1
        adaptive, default = Renderer(device, adaptive=True), Renderer(device)
        modes = {"all": (adaptive, False), "skip": (adaptive, True), "busy": (default, True)}
        best = dict.fromkeys(modes, math.inf)
        for _ in range(2):
            for mode, (renderer, skip) in modes.items():
                OpDef.still = still if skip else (lambda self, values: False)
                renderer.forget_frames()
                renderer.render(recipe.at(0), geom)  # the program, built or from the cache
                began = time.perf_counter()
                for k in range(n):
                    renderer.render(recipe.at(k / 30), geom)
                best[mode] = min(best[mode], (time.perf_counter() - began) / n * 1e3)
        OpDef.still = still
        a, b, c = (best[m] for m in modes)
        print(f"| {name} | {n} | {a:.1f} | {b:.1f} ({a / b:.2f}x) | {c:.1f} ({a / c:.2f}x) |")


def busy(device: str | None) -> None:
    """See the module: every blank-sheet sample at 960x640, halfway and at its
    end: the share of pixels adaptive sampling lists for the full pattern, and
    adaptive against full-pattern time (median of 7, interleaved)."""
    import json

    adaptive, full = Renderer(device, adaptive=True), Renderer(device, adaptive=False)
    print("\n## Adaptive against full pattern: blank-sheet samples at 960x640, ms, median of 7")
    print("| sample | time | listed | adaptive | full | ratio |")
    print("|---|---|---|---|---|---|")
    for path in sorted((ROOT / "samples").glob("*.json")):
        data = json.loads(path.read_text())
        if path.name == "recipe.schema.json" or "canvas" not in data:
            continue
        recipe = parse_recipe(data, path.name)
        geom = geometry(recipe.canvas, (960, 640))
        for t in sorted({recipe.end_time() / 2, recipe.end_time()}):
            spec = recipe.at(t)
            if spec.antialias == "none":
                continue
            times: dict[str, list[float]] = {"adaptive": [], "full": []}
            for _ in range(7):
                for name, renderer in (("adaptive", adaptive), ("full", full)):
                    began = time.perf_counter()
                    renderer.render(spec, geom)
                    times[name].append(time.perf_counter() - began)
            share = adaptive.last_full_pixels / (960 * 640)
            a, f = (statistics.median(times[k]) * 1e3 for k in ("adaptive", "full"))
            print(f"| {path.stem} | {t:g} s | {share:.2f} | {a:.1f} | {f:.1f} | {a / f:.2f} |")


def table1(device: str | None) -> None:
    adaptive, full = Renderer(device), Renderer(device, adaptive=False)
    print(f"\n## Table 1: blank-sheet design, 12 ops, kernel fps on {adaptive.info.name}")
    print("Each cell: ours best / median of 21 [full pattern, best] | paper (GeForce 8800GTS)")
    print("| size | " + " | ".join(COLUMNS) + " |")
    print("|---|" + "---|" * len(COLUMNS))
    for size, paper in PAPER.items():
        cells = []
        for col, ref in zip(COLUMNS, paper, strict=True):
            cell = kernel_cell(adaptive, full, recipe12(col), size, col != "none")
            cells.append(f"{cell} \\| {ref}")
        print(f"| {size[0]}x{size[1]} | " + " | ".join(cells) + " |", flush=True)


#: the bundled blank-sheet samples the svg part measures
SVG_SAMPLES = ("figure6", "nonpareil", "bouquet", "chevron", "spanish-wave", "stone-sprays")


def svg_part(device: str | None) -> None:
    """SVG export of every bundled blank-sheet sample: time, vertices and size at
    the default tolerance, and fidelity when zoomed, beside the raster renderer's
    own RGSS; then Figure 6 at 1024 px and at 4096 px at three tolerances."""
    import dataclasses

    import cairosvg

    from marblevideo.limits import DEFAULT_TOLERANCE
    from marblevideo.outputs.svg import design_svg
    from marblevideo.recipe import load_recipe

    def raster_svg(svg: str, size: tuple[int, int], k: int = 1) -> np.ndarray:
        png = cairosvg.svg2png(
            bytestring=svg.encode(), output_width=size[0] * k, output_height=size[1] * k
        )
        bgr = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
        rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
        return cv2.resize(rgb, size, interpolation=cv2.INTER_AREA) if k > 1 else rgb

    def within(a: np.ndarray, b: np.ndarray, levels: int = 24) -> float:
        d = np.abs(a[..., :3].astype(int) - b[..., :3].astype(int)).max(axis=-1)
        return 100 * float((d <= levels).mean())

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


LANES_CASES = ("blank 1024^2 RGSS", "720p walk", "720p reused", "720p planar walk")


def lanes_child(device: str | None) -> None:
    """One process of ``lanes``: ms per frame (median of 21) of LANES_CASES, as JSON."""
    import json

    from marblevideo.media.yuv import YuvMatrix

    renderer = Renderer(device)
    blank = parse_recipe(recipe12("rgss"), "lanes.json")
    over = parse_recipe({**recipe12("rgss"), "canvas": [1280, 720]}, "lanes.json")
    image = np.random.default_rng(1).integers(0, 255, (720, 1280, 4), dtype=np.uint8)
    planes = np.random.default_rng(2).integers(0, 255, (1080, 1280), dtype=np.uint8)
    matrix = YuvMatrix.of(None, None)
    geom_b = geometry(blank.canvas, (1024, 1024))
    geom_o = geometry(over.canvas, (1280, 720), (1280, 720))
    walk = Renderer(device, reuse_maps=False)
    runs = {
        LANES_CASES[0]: lambda: renderer.render(blank.at(0), geom_b),
        LANES_CASES[1]: lambda: walk.render(over.at(0), geom_o, image),
        LANES_CASES[2]: lambda: renderer.render(over.at(0), geom_o, image, static=True),
        LANES_CASES[3]: lambda: walk.render_i420(over.at(0), geom_o, planes, matrix, matrix),
    }
    out = {"lanes": f"{renderer.lanes} x {renderer.chains}", "device": renderer.info.name}
    out.update({name: median_time(fn) * 1e3 for name, fn in runs.items()})
    print(json.dumps(out))


def lanes(device: str | None) -> None:
    """16 against 8 (and 4) lanes for this CPU's code and for an AVX2 CPU's."""
    import json

    print("\n## Vector width: ms per frame, median of 21 (each width in its own process)")
    print("| target (device name) | lanes x chains | " + " | ".join(LANES_CASES) + " |")
    print("|---|---|" + "---|" * len(LANES_CASES))
    for target in (None, "avx2"):
        for width in (16, 8, 4):
            env = {**ENV, "MARBLEVIDEO_LANES": str(width)}
            env.pop("POCL_KERNELLIB_NAME", None)
            if target:
                env["POCL_KERNELLIB_NAME"] = target
            cmd = [sys.executable, __file__, "lanes-child"]
            cmd += ["--device", device] if device else []
            proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
            row = json.loads(proc.stdout.strip().splitlines()[-1])
            cells = " | ".join(f"{row[name]:.2f}" for name in LANES_CASES)
            name = f"{target or 'this CPU'} ({row['device']})"
            print(f"| {name} | {row['lanes']} | {cells} |", flush=True)


def cpu_summary() -> str:
    """The CPU's model and vector instruction sets (from /proc/cpuinfo)."""
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return platform.processor() or platform.machine()
    info = dict(
        (k.strip(), v.strip()) for k, _, v in (x.partition(":") for x in text.splitlines()) if v
    )
    flags = info.get("flags", "").split()
    vector = [f for f in flags if f.startswith(("avx", "sse4", "fma"))]
    return f"{info.get('model name', '?')}; flags: {' '.join(vector) or 'none of avx/sse4/fma'}"


def make_clip(path: Path, size=(1280, 720), seconds=4, fps=30, audio=True, keyint=None) -> Path:
    """A moving picture with audio, encoded quickly (the input of the e2e runs);
    ``keyint``: frames between keyframes (default x264's, 250)."""
    w, h = size
    yy, xx = np.mgrid[0:h, 0:w]
    options = {"preset": "ultrafast", "crf": "18", **({"g": str(keyint)} if keyint else {})}
    with av.open(str(path), "w") as out:
        v = out.add_stream("libx264", rate=fps, options=options)
        v.width, v.height, v.pix_fmt = w, h, "yuv420p"
        a = out.add_stream("aac", rate=48000, layout="stereo") if audio else None
        for i in range(seconds * fps):
            rgb = np.stack(
                [
                    (xx + 4 * i) % 256,
                    (yy * 2 + i) % 256,
                    ((xx // 40 + yy // 40 + i // 10) % 2) * 255,
                ],
                axis=2,
            )
            for p in v.encode(av.VideoFrame.from_ndarray(rgb.astype(np.uint8), "rgb24")):
                out.mux(p)
        out.mux(v.encode(None))
        if a is not None:
            tone = 0.2 * np.sin(np.arange(48000 * seconds) * 2 * np.pi * 440 / 48000)
            tone = np.stack([tone, tone]).astype(np.float32)
            for s0 in range(0, tone.shape[1], 1024):
                f = av.AudioFrame.from_ndarray(
                    np.ascontiguousarray(tone[:, s0 : s0 + 1024]), "fltp", "stereo"
                )
                f.sample_rate, f.pts = 48000, s0
                out.mux(a.encode(f))
            out.mux(a.encode(None))
    return path


#: the commands' environment: the repository importable, and bytecode cached as an
#: installed package's is (pip compiles it at install; a fresh compile is ~30 ms a run)
ENV = {
    **{k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"},
    # the checkout, then the caller's PYTHONPATH (wheels installed with --target)
    "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
}
PLAIN_SCRIPT = Path(__file__).resolve().parent / "plain_transcode.py"


def marble_command(clip: Path, recipe: Path, out: Path, device: str | None) -> list[str]:
    """The CLI marbling ``clip`` as the end-to-end and memory runs time it."""
    cmd = [sys.executable, "-m", "marblevideo", str(clip), "--ops", str(recipe), "-o", str(out)]
    cmd += ["-y", "-q", "--preset", "veryfast", "--crf", "23"]
    return cmd + (["--device", device] if device else [])


def animated12(seconds: float = 4) -> dict:
    """recipe12 with its wave's phase and its vortex's strength keyframed over
    ``seconds`` (the clip's length): every frame has new values, so no map is reused."""
    recipe = recipe12("rgss")
    wave, vortex = recipe["ops"][-2], recipe["ops"][-1]
    wave["phase"] = {"keys": [{"t": 0, "v": 0}, {"t": seconds, "v": 360}]}
    vortex["alpha"] = {"keys": [{"t": 0, "v": 0}, {"t": seconds, "v": 300, "ease": "ease-in-out"}]}
    return recipe


def e2e(device: str | None, seconds: int = 4) -> None:
    """The CLI on a 720p clip of ``seconds`` against a plain transcode, static and
    animated recipe.

    A static recipe keeps its maps from the first frame on (Renderer's reused
    maps); the animated one walks every frame. Two ratios: the whole command
    against the plain transcode run as a script in its own process (both pay
    Python's start and their imports), and per frame, where the CLI's fixed cost
    (process start, imports, OpenCL set-up, the first frames: the CLI on the
    clip's first 0.1 s) is taken off and set against the in-process transcode.
    The fixed cost weighs less on a longer clip: run it with several lengths.
    """
    import json

    fps, fixed_end = 30, 0.1
    n = seconds * fps
    fixed_frames = math.ceil(fixed_end * fps)  # frames at t = 0, 1/30, 2/30
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        clip = make_clip(tmp / "clip.mp4", seconds=seconds, fps=fps)
        recipes = {
            "static": recipe12("rgss"),
            "animated": animated12(seconds),
            "animated, --exact-walk": animated12(seconds),
        }
        cmds = {}
        for k, (name, recipe) in enumerate(recipes.items()):
            (tmp / f"r{k}.json").write_text(json.dumps(recipe))
            cmds[name] = marble_command(clip, tmp / f"r{k}.json", tmp / "out.mp4", device)
            cmds[name] += ["--exact-walk"] if "exact" in name else []
            subprocess.run(cmds[name], check=True, env=ENV)  # warm the kernel cache
        cmds["fixed"] = cmds["static"] + ["--end", str(fixed_end)]
        cmds["script"] = [sys.executable, str(PLAIN_SCRIPT), str(clip), str(tmp / "plain.mp4")]
        times: dict[str, list[float]] = {"plain": [], **{k: [] for k in cmds}}
        for _ in range(5):  # each round runs every command once: ratios are paired
            t = time.perf_counter()
            plain_transcode(clip, tmp / "plain.mp4")
            times["plain"].append(time.perf_counter() - t)
            for name, cmd in cmds.items():
                t = time.perf_counter()
                subprocess.run(cmd, check=True, env=ENV)
                times[name].append(time.perf_counter() - t)
        med = {k: statistics.median(v) for k, v in times.items()}
        p = med["plain"]
        print(
            f"\n## End to end: 1280x720, {seconds} s ({n} frames), 12 ops RGSS, "
            "x264 veryfast crf 23"
        )
        print(f"plain PyAV decode+encode, in process: {p:.2f} s ({p / n * 1e3:.1f} ms/frame)")
        print(f"the same as a script (its own process): {med['script']:.2f} s")
        fixed = med["fixed"]
        print(f"CLI fixed cost (start, set-up, first frames; --end {fixed_end}): {fixed:.2f} s")
        rounds = list(zip(times["plain"], times["script"], times["fixed"], strict=True))
        for name in recipes:
            o = med[name]
            whole = [t / sc for t, (_, sc, _) in zip(times[name], rounds, strict=True)]
            frame = [
                (t - fx) / (n - fixed_frames) / (pl / n)
                for t, (pl, _, fx) in zip(times[name], rounds, strict=True)
            ]
            print(
                f"marblevideo CLI, {name + ' recipe:':32} {o:.2f} s ({o / n * 1e3:.1f} ms/frame); "
                f"whole command {statistics.median(whole):.2f}x the script (best "
                f"{min(whole):.2f}); per frame {statistics.median(frame):.2f}x (best "
                f"{min(frame):.2f}); medians of 5 paired rounds"
            )
        print("targets (whole command): static <= 1.3x, animated <= 2.0x (issue 35)")


def turn12(seconds: float, antialias: str) -> dict:
    """One op, the tank turned 0 -> 30 degrees over ``seconds``: a walk of next to
    nothing, no ink, every sample gathered."""
    return {
        "marblevideo": 1,
        "canvas": [1024, 1024],
        "antialias": antialias,
        "ops": [
            {
                "type": "turn",
                "center": [512, 512],
                "angle": {"keys": [{"t": 0, "v": 0}, {"t": seconds, "v": 30}]},
            }
        ],
    }


def bounds(device: str | None, seconds: int = 10) -> None:
    """Lower bounds for animated marbling of the e2e clip, whole commands against
    the plain transcode script, in the same paired rounds as e2e's.

    - the animated recipe with antialias "none": every pixel walked once and
      sampled once, the best case of any adaptive scheme that walks each pixel
      at least once (nothing more anywhere, no classification, no lists);
    - one keyed turn, RGSS and "none": the pattern's gathers, and one gather,
      with a walk of next to nothing;
    - the plain transcode of the animated output: what x264 pays for marbled
      pictures beyond the clip's own (the encoder's share of the ratio).
    """
    import json

    fps = 30
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        clip = make_clip(tmp / "clip.mp4", seconds=seconds, fps=fps)
        animated_none = {**animated12(seconds), "antialias": "none"}
        recipes = {
            "animated 12 ops, rgss": animated12(seconds),
            "animated 12 ops, none": animated_none,
            "1 keyed turn, rgss": turn12(seconds, "rgss"),
            "1 keyed turn, none": turn12(seconds, "none"),
        }
        cmds: dict[str, list[str]] = {}
        for k, (name, recipe) in enumerate(recipes.items()):
            (tmp / f"r{k}.json").write_text(json.dumps(recipe))
            cmds[name] = marble_command(clip, tmp / f"r{k}.json", tmp / f"o{k}.mp4", device)
            subprocess.run(cmds[name], check=True, env=ENV)  # warm the kernel cache
        script = [sys.executable, str(PLAIN_SCRIPT)]
        cmds["plain transcode of the clip"] = [*script, str(clip), str(tmp / "p.mp4")]
        marbled = tmp / "o0.mp4"  # the animated RGSS output, written above
        cmds["plain transcode of the marbled output"] = [*script, str(marbled), str(tmp / "q.mp4")]
        times: dict[str, list[float]] = {k: [] for k in cmds}
        for _ in range(5):
            for name, cmd in cmds.items():
                t = time.perf_counter()
                subprocess.run(cmd, check=True, env=ENV)
                times[name].append(time.perf_counter() - t)
        base = times["plain transcode of the clip"]
        print(f"\n## Bounds: 1280x720, {seconds} s ({seconds * fps} frames), x264 veryfast crf 23")
        print("| command | seconds | whole command against the plain script (best) |")
        print("|---|---|---|")
        for name, ts in times.items():
            ratios = [t / b for t, b in zip(ts, base, strict=True)]
            print(
                f"| {name} | {statistics.median(ts):.2f} | "
                f"{statistics.median(ratios):.2f}x ({min(ratios):.2f}x) |"
            )
        print("medians of 5 paired rounds; the bar (animated): <= 1.8x")


def numpy_frame(spec, geom, image: np.ndarray) -> np.ndarray:
    """The recipe per frame as a NumPy user would: float32 maps, cv2.remap per subsample."""
    h, w = image.shape[:2]
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    acc = np.zeros((h, w, 4), np.float32)
    for dx, dy, wgt in (
        (-1 / 8, -3 / 8, 0.25),
        (3 / 8, -1 / 8, 0.25),
        (1 / 8, 3 / 8, 0.25),
        (-3 / 8, 1 / 8, 0.25),
    ):
        cx = (xx + 0.5 + dx) * geom.to_canvas[0] + geom.to_canvas[2]
        cy = (yy + 0.5 + dy) * geom.to_canvas[1] + geom.to_canvas[3]
        x0, y0, ink = inverse_walk(spec, cx.astype(np.float32), cy.astype(np.float32))
        mx = (x0 * geom.to_input[0] + geom.to_input[2] - 0.5).astype(np.float32)
        my = (y0 * geom.to_input[1] + geom.to_input[3] - 0.5).astype(np.float32)
        sample = cv2.remap(image, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        sample = sample.astype(np.float32)
        for i in np.unique(ink[ink >= 0]):
            sample[ink == i] = (*spec.ops[i].values["color"], 255)
        acc += wgt * sample
    return np.floor(acc + 0.5).astype(np.uint8)


def numpy_baseline(device: str | None) -> None:
    recipe = parse_recipe(recipe12("rgss"), "r.json")
    rng = np.random.default_rng(0)
    image = rng.integers(0, 256, (720, 1280, 4), dtype=np.uint8)
    spec, geom = recipe.at(0), geometry(recipe.canvas, (1280, 720), (1280, 720))
    renderer = Renderer(device, reuse_maps=False)  # both sides walk every frame
    ours = median_time(lambda: renderer.render(spec, geom, image))
    base = median_time(lambda: numpy_frame(spec, geom, image), repeat=3, warmup=0)
    print("\n## Against NumPy float32 + cv2.remap, 1280x720, 12 ops RGSS, per frame")
    print(
        f"NumPy + cv2.remap: {base * 1e3:.0f} ms; marblevideo: {ours * 1e3:.1f} ms; "
        f"speed-up {base / ours:.0f}x (target >= 20x)"
    )


def peak_rss_mb(cmd: list[str], env: dict) -> float:
    proc = subprocess.Popen(cmd, env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    if status != 0:
        raise SystemExit(f"failed: {' '.join(cmd)}")
    return usage.ru_maxrss / 1024


def looped(src: Path, dst: Path, times: int) -> Path:
    """``src`` played ``times`` over, by stream copy: a long clip in seconds, not minutes."""
    with av.open(str(src)) as inp:
        ends: dict[int, int] = {}
        for packet in inp.demux():
            if packet.pts is not None:
                end = packet.pts + (packet.duration or 0)
                ends[packet.stream.index] = max(ends.get(packet.stream.index, 0), end)
    with av.open(str(src)) as inp, av.open(str(dst), "w") as out:
        streams = {s.index: out.add_stream_from_template(s) for s in inp.streams}
        for k in range(times):
            inp.seek(0)
            for packet in inp.demux():
                if packet.dts is None:
                    continue
                shift = k * ends[packet.stream.index]
                packet.pts += shift
                packet.dts += shift
                packet.stream = streams[packet.stream.index]
                out.mux(packet)
    return dst


def memory(device: str | None, long_seconds: int = 600) -> None:
    """Peak RSS against clip length. The render's buffers are fixed per frame size,
    so a light recipe (one wave, no AA) keeps the 10-minute run near 10 minutes;
    the encoder settings are those of the e2e run."""
    import json

    light = {
        "marblevideo": 1,
        "antialias": "none",
        "ops": [{"type": "wave", "amplitude": 20, "wavelength": 300, "phase": 0, "angle": 30}],
    }
    print("\n## Peak RSS of the CLI, 1920x1080 at 30 fps, one wave, x264 veryfast (MB)")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        (tmp / "r.json").write_text(json.dumps(light))
        short = make_clip(tmp / "c10.mp4", (1920, 1080), 10, 30)
        clips = [(10, short)]
        if long_seconds > 10:
            clips.append((long_seconds, looped(short, tmp / "long.mp4", long_seconds // 10)))
        for seconds, clip in clips:
            cmd = marble_command(clip, tmp / "r.json", tmp / "o.mp4", device)
            t = time.perf_counter()
            rss = peak_rss_mb(cmd, ENV)
            print(
                f"{seconds:>4} s clip: peak RSS {rss:.0f} MB "
                f"({time.perf_counter() - t:.0f} s wall)",
                flush=True,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("parts", nargs="*", default=["table1", "e2e", "numpy", "memory"])
    # lanes-child: one process of `lanes` (internal)
    parser.add_argument("--device", help="OpenCL device (see `marblevideo devices`)")
    parser.add_argument(
        "--long", type=int, default=600, help="seconds of the long memory clip (default 600)"
    )
    parser.add_argument(
        "--seconds",
        type=int,
        nargs="+",
        default=[4, 20],
        metavar="S",
        help="lengths of the e2e clips in seconds (default 4 20)",
    )
    args = parser.parse_args()
    if args.parts == ["lanes-child"]:
        return lanes_child(args.device)
    print(f"# {platform.node()}, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M')}")
    print(f"# CPU: {cpu_summary()}")
    for part in args.parts:
        if part == "cluster":
            from cluster_bench import cluster_part

            cluster_part(args.device, make_clip, animated12)
        elif part in ("lattice", "live1080"):
            from lattice_bench import cost_part, lattice_part, live1080_part

            if part == "lattice":
                lattice_part(args.device, animated12)
                cost_part(args.device, animated12, turn12)
            else:
                live1080_part(args.device)
        elif part == "strokes":
            from stroke_bench import strokes_part

            strokes_part(args.device)
        elif part == "memory":
            memory(args.device, args.long)
        elif part in ("e2e", "bounds"):
            for seconds in args.seconds:
                (e2e if part == "e2e" else bounds)(args.device, seconds)
        else:
            parts = {
                "table1": table1,
                "pst": pst_row,
                "e2e": e2e,
                "numpy": numpy_baseline,
                "lanes": lanes,
                "svg": svg_part,
                "bullseye": bullseye,
                "series": series,
                "animations": animations,
                "busy": busy,
            }
            parts[part](args.device)


if __name__ == "__main__":
    main()
