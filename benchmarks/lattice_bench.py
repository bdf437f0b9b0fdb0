"""The interpolated inverse map against the exact walk: quality and time.

    python -m benchmarks lattice          # quality and kernel time
    python -m benchmarks live1080         # marblevideo live at 1080p, lattice and exact
    python -m benchmarks lattice e2e live1080 --seconds 10   # the whole comparison

- lattice: frames over the e2e clip's picture (1280x720: two ramps and a
  40-pixel checker that moves per frame) of the animated 12-op recipe at
  several times, and of the busy samples (nonpareil, bouquet, chevron) over
  the same picture at 960x640 halfway and at their end, each rendered
  exactly and from the lattice by one renderer (RGBA and I420 planes), and
  more samples over it halfway (figure6, swirl, comb-wave, spanish-wave,
  stone-sprays): the share of pixels (plane samples) within 1 and 2 levels of
  the exact walk, the largest difference, the share of cells walked exactly,
  and ms per frame of each (median of 5, interleaved); then what a 720p I420
  frame costs walked and interpolated by how much there is to walk (one keyed
  turn, three smooth ops, the 12-op recipe, nonpareil; best of 31, which
  MIN_WALKED_OPS rests on).
- live1080: benchmarks.live_bench at 1920x1080 with the animated 12-op
  recipe, with the lattice (the default) and with --exact-walk, alternating,
  two rounds each (fps, latency median and p95, render median).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time

import numpy as np

from marblevideo.media.yuv import YuvMatrix
from marblevideo.opencl.renderer import Renderer
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference.yuv import rgba_to_i420

from .common import ENV, ROOT

BUSY = ("nonpareil", "bouquet", "chevron")
#: more samples over the clip, halfway through: where the lattice pays and where not
OTHERS = ("figure6", "swirl", "comb-wave", "spanish-wave", "stone-sprays")


def clip_frame(i: int, w: int, h: int) -> np.ndarray:
    """Frame ``i`` of bench.make_clip's picture, RGBA (before its lossy encode)."""
    yy, xx = np.mgrid[0:h, 0:w]
    planes = [(xx + 4 * i) % 256, (yy * 2 + i) % 256, ((xx // 40 + yy // 40 + i // 10) % 2) * 255]
    return np.stack([*planes, np.full_like(xx, 255)], axis=2).astype(np.uint8)


def compare(renderer: Renderer, spec, geom, image: np.ndarray, planar: bool) -> dict:
    """Quality and time of one frame from the lattice against the exact walk."""
    matrix = YuvMatrix.of(1, 1)
    planes = rgba_to_i420(image, matrix) if planar else None

    def draw(lattice: bool) -> np.ndarray:
        if planar:
            return renderer.render_i420(spec, geom, planes, matrix, matrix, lattice=lattice)
        return renderer.render(spec, geom, image, lattice=lattice)

    before = renderer.lattice_walk.frames
    exact, fast = draw(False), draw(True)
    used = renderer.lattice_walk.frames > before  # else too few ops (MIN_WALKED_OPS)
    refined = renderer.lattice_walk.refined_share() if used else None
    d = np.abs(exact.astype(np.int16) - fast.astype(np.int16))
    d = d.max(axis=2) if d.ndim == 3 else d
    times: dict[bool, list[float]] = {False: [], True: []}
    for _ in range(5):
        for lattice in (False, True):
            began = time.perf_counter()
            draw(lattice)
            times[lattice].append(time.perf_counter() - began)
    ms = {k: statistics.median(v) * 1e3 for k, v in times.items()}
    return {
        "within1": float((d <= 1).mean()),
        "within2": float((d <= 2).mean()),
        "largest": int(d.max()),
        "refined": refined,
        "exact_ms": ms[False],
        "lattice_ms": ms[True],
    }


def row(name: str, when: str, path: str, q: dict) -> str:
    walked = "walked (few ops)" if q["refined"] is None else f"{q['refined']:.2f}"
    return (
        f"| {name} | {when} | {path} | {q['within1'] * 100:.3f}% | {q['within2'] * 100:.3f}% | "
        f"{q['largest']} | {walked} | {q['exact_ms']:.1f} | {q['lattice_ms']:.1f} |"
    )


def lattice_part(device: str | None, animated12) -> None:
    """See the module: the quality table, printed as markdown."""
    renderer = Renderer(device, reuse_maps=False)
    print("\n## The lattice against the exact walk (RGSS; ms per frame, median of 5 interleaved)")
    head = "frames | time | path | within 1 | within 2 | largest | cells walked | exact | lattice"
    print(f"| {head} |")
    print("|---|---|---|---|---|---|---|---|---|")
    recipe = parse_recipe(animated12(10), "animated12")
    geom = geometry(recipe.canvas, (1280, 720), (1280, 720))
    for t in (1.0, 3.0, 5.0, 7.0, 9.0):
        image = clip_frame(int(t * 30), 1280, 720)
        for planar in (False, True):
            q = compare(renderer, recipe.at(t, recipe.canvas), geom, image, planar)
            print(row("clip, 12-op animated", f"{t:g} s", "I420" if planar else "RGBA", q))
    for name in BUSY + OTHERS:
        data = json.loads((ROOT / "samples" / f"{name}.json").read_text())
        recipe = parse_recipe({**data, "antialias": "rgss"}, name)
        geom = geometry(recipe.canvas, (960, 640), (960, 640))
        end = recipe.end_time()
        for t in (end / 2, end) if name in BUSY else (end / 2,):
            q = compare(renderer, recipe.at(t), geom, clip_frame(int(t * 30), 960, 640), False)
            print(row(f"{name} over the clip", f"{t:g} s", "RGBA", q))
    print(
        "within: share of pixels (I420: samples) within 1 / 2 levels of the exact walk; "
        "cells walked: share of the 8x8 cells walked exactly"
    )


def live1080_part(device: str | None) -> None:
    """See the module: live_bench at 1920x1080, lattice against exact, alternating."""
    base = [
        sys.executable,
        "-m",
        "benchmarks.live_bench",
        "--size",
        "1920x1080",
        "--twelve",
        "--seconds",
        "10",
    ]
    base += ["--device", device] if device else []
    print("\n## Live at 1920x1080, animated 12 ops RGSS (live_bench.py --twelve), 2 rounds each")
    print("| walk | fps | latency median / p95 ms | render median ms |")
    print("|---|---|---|---|")
    for _ in range(2):
        for name, extra in (("lattice", []), ("exact (--exact-walk)", ["--exact-walk"])):
            run = {"cwd": ROOT, "env": ENV, "capture_output": True, "text": True}
            out = subprocess.run(base + extra, check=True, **run).stdout
            r = json.loads(out.strip().splitlines()[-1])
            print(
                f"| {name} | {r['fps']} | {r['latency_median_ms']} / {r['latency_p95_ms']} | "
                f"{r['render_median_ms']} |"
            )
    print("target: 30 fps, latency < 100 ms")


def smooth3() -> dict:
    """Three smooth ops (a wave, a wide vortex, a turn), keyed: no ink, a map the
    lattice interpolates nearly everywhere."""
    ops = [
        {"type": "wave", "amplitude": 10, "wavelength": 400, "phase": 30, "angle": 90},
        {"type": "vortex", "center": [640, 360], "alpha": 300, "lambda": 200},
        {
            "type": "turn",
            "center": [640, 360],
            "angle": {"keys": [{"t": 0, "v": 0}, {"t": 10, "v": 20}]},
        },
    ]
    return {"marblevideo": 1, "canvas": [1280, 720], "antialias": "rgss", "ops": ops}


def cost_part(device: str | None, animated12, turn12) -> None:
    """What a frame costs walked and interpolated, by how much there is to walk:
    720p I420 (the video path), best and median of 31 interleaved, lattice taken
    whatever the number of ops (min_ops 1)."""
    matrix = YuvMatrix.of(1, 1)
    renderer = Renderer(device, reuse_maps=False)
    renderer.lattice_walk.min_ops = 1
    planes = rgba_to_i420(clip_frame(150, 1280, 720), matrix)
    nonpareil = json.loads((ROOT / "samples" / "nonpareil.json").read_text())
    cases = (
        ("one keyed turn", turn12(10, "rgss"), 5.0),
        ("three smooth ops", smooth3(), 5.0),
        ("12-op animated", animated12(10), 5.0),
        ("nonpareil", {**nonpareil, "antialias": "rgss"}, 3.0),
    )
    print("\n## What the lattice saves, by the walk: 1280x720 I420 RGSS, ms, best / median of 31")
    print("| recipe | cells walked | exact | lattice |")
    print("|---|---|---|---|")
    for name, data, t in cases:
        recipe = parse_recipe(data, name)
        geom = geometry(recipe.canvas, (1280, 720), (1280, 720))
        spec = recipe.at(t, recipe.canvas)
        times: dict[bool, list[float]] = {False: [], True: []}
        for _ in range(31):
            for lattice in (False, True):
                began = time.perf_counter()
                renderer.render_i420(spec, geom, planes, matrix, matrix, lattice=lattice)
                times[lattice].append(time.perf_counter() - began)
        e, f = (
            f"{min(times[k]) * 1e3:.1f} / {statistics.median(times[k]) * 1e3:.1f}"
            for k in (False, True)
        )
        print(f"| {name} | {renderer.lattice_walk.refined_share():.2f} | {e} | {f} |")
