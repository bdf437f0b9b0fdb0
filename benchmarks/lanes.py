"""The lanes part: 16 against 8 (and 4) lanes, for this CPU's code and for an
AVX2 CPU's (POCL_KERNELLIB_NAME=avx2), each width in a process of its own
(``python -m benchmarks lanes-child``)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from marblevideo.opencl.renderer import Renderer
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

from .common import ENV, ROOT, median_time, recipe12

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
            cmd = [sys.executable, "-m", "benchmarks", "lanes-child"]
            cmd += ["--device", device] if device else []
            run = {"cwd": ROOT, "env": env, "capture_output": True, "text": True}
            proc = subprocess.run(cmd, check=True, **run)
            row = json.loads(proc.stdout.strip().splitlines()[-1])
            cells = " | ".join(f"{row[name]:.2f}" for name in LANES_CASES)
            name = f"{target or 'this CPU'} ({row['device']})"
            print(f"| {name} | {row['lanes']} | {cells} |", flush=True)
