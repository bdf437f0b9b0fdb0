"""Benchmark of ``marblevideo live``: frames per second and capture-to-preview latency.

Runs the real pipeline in process: the built-in test pattern (1280x720 at 30 fps
by default) -> a 6-op animated recipe with RGSS antialiasing -> JPEG (quality 80)
-> the preview server, with one HTTP client reading the MJPEG stream. Latency is
the time from a frame's capture timestamp to its JPEG being ready to send.

    python -m benchmarks.live_bench [--size 1280x720] [--seconds 10]
        [--preview-width 640] [--record out.mp4] [--device P:D] [--motion]

``--motion``: the source is a looped clip of six textured discs going round
(:mod:`benchmarks.motion_clip`, decoded by PyAV at its own pace as a file source
is) and the recipe the ``dance`` preset (two keyed waves and ``motion``, six
strokes at most): six motion strokes active, growing while their discs move.
Reported besides: each frame's time (tracker and render) median and p95, the
motion strokes and their points at the end, the ops walked per frame.

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import json
import platform
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

RECIPE = {
    "marblevideo": 1,
    "canvas": [1280, 720],
    "antialias": "rgss",
    "edges": "mirror",
    "ops": [
        {"type": "drop", "center": [640, 360], "radius": 120, "color": "#1d4e89"},
        {"type": "comb", "point": [0, 0], "angle": 0, "spacing": 90, "alpha": 60, "lambda": 20},
        {
            "type": "wave",
            "amplitude": {"keys": [{"t": 0, "v": 0}, {"t": 2, "v": 25}]},
            "wavelength": 280,
            "phase": {"keys": [{"t": 0, "v": 0}, {"t": 10, "v": 1800}]},
            "angle": 90,
        },
        {"type": "tine", "point": [640, 0], "angle": 90, "alpha": 80, "lambda": 30},
        {
            "type": "circle",
            "center": [640, 360],
            "radius": 260,
            "lambda": 60,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 5, "v": -300}, {"t": 10, "v": 0}]},
        },
        {
            "type": "vortex",
            "center": {"keys": [{"t": 0, "v": [560, 360]}, {"t": 10, "v": [720, 360]}]},
            "lambda": 140,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 5, "v": 900}, {"t": 10, "v": 0}]},
        },
    ],
}


def _reader(url: str, stop: threading.Event, counter: list[int]) -> None:
    with urllib.request.urlopen(url, timeout=10) as stream:
        while not stop.is_set():
            chunk = stream.read(65536)
            if not chunk:
                return
            counter[0] += chunk.count(b"--marblevideoframe")


def bench(
    size,
    seconds,
    warmup,
    preview_width,
    record,
    device,
    fps,
    recipe_dict=RECIPE,
    lattice=True,
    motion=False,
):
    from marblevideo.cli.arguments import parse_size
    from marblevideo.live.session import LiveSession
    from marblevideo.live.sources import MediaSource, TestPattern
    from marblevideo.serve.server import Server

    w, h = parse_size(size)
    with tempfile.TemporaryDirectory() as tmp:
        recipe = Path(tmp) / "bench.json"
        recipe.write_text(json.dumps(recipe_dict))
        if motion:
            from .motion_clip import six_discs

            source = MediaSource(str(six_discs(size=(w, h), fps=round(fps))), loop=True)
        else:
            source = TestPattern((w, h), fps)
        session = LiveSession(
            recipe,
            source,
            device=device,
            jpeg=True,
            preview_width=preview_width,
            quiet=True,
            lattice=lattice,
        )
        recorder = None
        if record:
            from marblevideo.cli.live import build_parser, recorder_for

            args = build_parser().parse_args(["--ops", str(recipe), "-o", record, "-y"])
            recorder = recorder_for(args, record)
            recorder.start(w, h, fps)
            session.recorder = recorder
        frame_s: list[float] = []  # each frame's time after the warm-up (tracker and render)
        shown = session.meters.frame

        def frame(now: float, render_s: float) -> None:
            if "start" in marks:
                frame_s.append(render_s)
            shown(now, render_s)

        session.meters.frame = frame
        server = Server(session, 0)
        server.start()
        stop = threading.Event()
        received = [0]
        client = threading.Thread(
            target=_reader, args=(server.url + "stream.mjpg", stop, received), daemon=True
        )
        client.start()
        marks = {}

        def sample():
            time.sleep(warmup)
            marks["start"] = (
                time.monotonic(),
                session.frames,
                received[0],
                session.source.frames.dropped,
            )
            session.meters.clear()
            time.sleep(seconds)
            marks["end"] = (
                time.monotonic(),
                session.frames,
                received[0],
                session.source.frames.dropped,
            )
            session.stats_at_end = session.stats()
            session.motion_at_end = session.motion.state()
            session.stop_event.set()

        threading.Thread(target=sample, daemon=True).start()
        try:
            session.run()
        finally:
            stop.set()
            server.stop()
            session.close()
            if recorder is not None:
                recorder.close()
        (t0, f0, r0, d0), (t1, f1, r1, d1) = marks["start"], marks["end"]
        stats, moved = session.stats_at_end, session.motion_at_end
        ms = sorted(1000 * x for x in frame_s)
        return {
            "size": f"{w}x{h}",
            "source_fps": fps,
            "preview_width": preview_width or w,
            "record": bool(record),
            "fps": round((f1 - f0) / (t1 - t0), 1),
            "preview_fps_received": round((r1 - r0) / (t1 - t0), 1),
            "latency_median_ms": stats["latency_ms"],
            "latency_p95_ms": stats["latency_p95_ms"],
            "render_median_ms": stats["render_ms"],
            "source_dropped": stats["dropped"],
            "dropped_measured": d1 - d0,
            "frame_median_ms": round(ms[len(ms) // 2], 1) if ms else None,
            "frame_p95_ms": round(ms[int(0.95 * (len(ms) - 1))], 1) if ms else None,
            "motion_strokes": len(moved["strokes"]),
            "motion_points": sum(len(op["points"]) for op in moved["strokes"]),
            "ops_per_frame": len(recipe_dict["ops"]) + len(moved["strokes"]),
            "programs_built": session.renderer.programs.built,
            "device": session.renderer.info.name,
        }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size", default="1280x720")
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--warmup", type=float, default=2.0)
    p.add_argument("--fps", type=float, default=30.0, help="test pattern rate")
    p.add_argument("--preview-width", type=int)
    p.add_argument("--record", help="also record to this file")
    p.add_argument("--device")
    p.add_argument(
        "--twelve",
        action="store_true",
        help="the end-to-end runs' animated 12-op recipe (common.animated12) instead",
    )
    p.add_argument(
        "--exact-walk", action="store_true", help="walk every subsample (no lattice; issue 35)"
    )
    p.add_argument(
        "--motion",
        action="store_true",
        help="six discs going round (a looped clip) through the dance preset (motion)",
    )
    p.add_argument(
        "--without-motion",
        action="store_true",
        help="with --motion: the same source and recipe without its motion (the baseline)",
    )
    args = p.parse_args()
    recipe = RECIPE
    if args.motion:
        from marblevideo.bundled import presets

        recipe = json.loads(presets()["dance"].read_text())
        if args.without_motion:
            del recipe["motion"]
    if args.twelve:
        from .common import animated12

        recipe = animated12(args.seconds + args.warmup)
    result = bench(
        args.size,
        args.seconds,
        args.warmup,
        args.preview_width,
        args.record,
        args.device,
        args.fps,
        recipe,
        lattice=not args.exact_walk,
        motion=args.motion,
    )
    result["recipe"] = "12-op animated" if args.twelve else "6-op animated"
    if args.motion:
        result["recipe"] = "dance (2 keyed waves" + ")" * args.without_motion
        result["recipe"] += "" if args.without_motion else ", motion)"
    result["walk"] = "exact" if args.exact_walk else "lattice"
    result["machine"] = f"{platform.machine()} {platform.processor() or ''}".strip()
    print(json.dumps(result))


if __name__ == "__main__":
    main()
