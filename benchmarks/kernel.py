"""Kernel parts: the paper's Table 1, the pst-style row, concentric drops walked
as one run, closed-form series, animations with ops not yet started, busy
designs, and the NumPy + cv2.remap baseline (kernel time: render and read back)."""

from __future__ import annotations

import math
import statistics
import time

import cv2
import numpy as np

from marblevideo.opencl.renderer import Renderer
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import inverse_walk

from .common import ROOT, median_time, recipe12, timings

PAPER = {  # Table 1 of Lu et al. 2012: GeForce 8800GTS, frames per second
    (512, 512): (1560, 732, 250, 239),
    (1024, 512): (1265, 375, 125, 120),
    (1024, 768): (850, 246, 83, 80),
    (1024, 1024): (660, 189, 64, 61),
    (1280, 1024): (548, 156, 55, 53),
}
COLUMNS = ("none", "rgss", "checker4", "grid4")


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
    """See the package's docstring: ms per 1024x1024 blank-sheet frame, full RGSS, both
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
    """See the package's docstring: the bundled samples with rakes and the pst design (rakes
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
    """See the package's docstring: every frame of sample animations at 960x640 (30 fps,
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
    """See the package's docstring: every blank-sheet sample at 960x640, halfway and at its
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
