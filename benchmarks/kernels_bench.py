"""Time per frame, and with ``--profile`` per kernel, of the e2e clip's frames.

    python -m benchmarks kernels              # ms per frame of each route
    python -m benchmarks kernels --profile    # and each kernel's device time

Frames of the e2e clip's picture (1280x720) through one renderer, as the CLI
draws them: I420 planes with the static 12-op recipe (the table of reused maps
filled once, then fetched), the animated recipe walked exactly and from the
lattice, and the animated recipe as RGBA. ``--profile`` renders on a profiling
queue (``Renderer(profile=True)``: each launch's event kept, OpenCL's
start and end times) and prints, per route, each kernel's launches and device
milliseconds per frame beside the frame's wall time; the rest is the host's
share (packing, copies, waits).
"""

from __future__ import annotations

import statistics
import time

from marblevideo.media.yuv import YuvMatrix
from marblevideo.opencl.renderer import Renderer
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference.yuv import rgba_to_i420

from .common import animated12, recipe12
from .lattice_bench import clip_frame

#: frames of each route after its first (the first builds and fills tables)
FRAMES = 30
SIZE = (1280, 720)


def routes() -> dict:
    """Route name -> (recipe, planar, lattice, static) as the CLI would take them."""
    animated = parse_recipe(animated12(10), "animated12")
    static = parse_recipe(recipe12("rgss"), "recipe12")
    return {
        "I420, static recipe (reused maps)": (static, True, False, True),
        "I420, animated, lattice": (animated, True, True, False),
        "I420, animated, exact walk": (animated, True, False, False),
        "RGBA, animated, exact walk": (animated, False, False, False),
    }


def run_route(renderer: Renderer, recipe, planar: bool, lattice: bool, static: bool) -> list:
    """Seconds of each of FRAMES frames (the first, untimed, before them)."""
    matrix = YuvMatrix.of(1, 1)
    geom = geometry(recipe.canvas, SIZE, SIZE)
    images = [clip_frame(i, *SIZE) for i in range(4)]
    inputs = [rgba_to_i420(im, matrix) for im in images] if planar else images
    times = []
    for i in range(FRAMES + 1):
        spec = recipe.at(i / 30, recipe.canvas)
        frame = inputs[i % len(inputs)]
        began = time.perf_counter()
        if planar:
            opts = dict(static=static, lattice=lattice)
            renderer.render_i420(spec, geom, frame, matrix, matrix, **opts)
        else:
            renderer.render(spec, geom, frame, static=static, lattice=lattice)
        times.append(time.perf_counter() - began)
        if i == 0:
            renderer.device_queue.kernel_times()  # the first frame's launches left out
    return times[1:]


def kernels_part(device: str | None, profile: bool) -> None:
    """See the module."""
    renderer = Renderer(device, profile=profile)
    print(f"\n## Frames of the e2e clip (1280x720), {FRAMES} each after one untimed")
    if profile:
        print("(a profiling queue: per kernel, device ms per frame; 'launches' per frame)")
    print("| route | kernel | launches | ms per frame |")
    print("|---|---|---|---|")
    for name, (recipe, planar, lattice, static) in routes().items():
        times = run_route(renderer, recipe, planar, lattice, static)
        kernels = renderer.device_queue.kernel_times()
        device_ms = 0.0
        for kernel, (count, seconds) in sorted(kernels.items(), key=lambda kv: -kv[1][1]):
            device_ms += seconds * 1e3 / FRAMES
            print(f"| {name} | {kernel} | {count / FRAMES:g} | {seconds * 1e3 / FRAMES:.2f} |")
        if kernels:
            print(f"| {name} | all kernels | | {device_ms:.2f} |")
        print(
            f"| {name} | **whole frame (wall, median)** | | {statistics.median(times) * 1e3:.2f} |"
        )
