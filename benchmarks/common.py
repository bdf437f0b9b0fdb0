"""What the benchmark parts share: the recipes they time, the timer, the clip
they marble, the CLI's command line and environment, the machine's summary."""

from __future__ import annotations

import os
import platform
import statistics
import sys
import time
from pathlib import Path

import av
import numpy as np

#: The checkout (the folder holding marblevideo/ and benchmarks/).
ROOT = Path(__file__).resolve().parent.parent


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


ENV = {
    **{k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"},
    # the checkout, then the caller's PYTHONPATH (wheels installed with --target)
    "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
}
#: plain_transcode.py stays a script of its own (it imports nothing of ours)
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


def header() -> None:
    """The machine, the date and the CPU's vector flags, as every report begins."""
    print(f"# {platform.node()}, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M')}")
    print(f"# CPU: {cpu_summary()}")
