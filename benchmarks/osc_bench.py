"""Benchmark of controller latency in ``marblevideo live``: from an OSC message
sent over UDP on loopback to the preview's JPEG showing it, at 1280x720.

Runs the real pipeline in process: a still source (the same 1280x720 picture
published at 30 fps, so a frame changes only when the controller does) -> the
6-op recipe of ``live_bench.py`` with the vortex's alpha following
``osc:/swirl`` (RGSS) -> JPEG (quality 80) -> the session's latest JPEG, with
an OSC listener (``--osc``) feeding the session's controllers. Each round sends
0 or 1 to /swirl at a random phase of the frame clock and waits for the first
JPEG that is nearer the picture of the new value than of the old one (the
time is taken when the JPEG is handed over, before it is decoded, at a quarter
of its size, to check; the check shares the CPU with the session).
The session's own capture -> JPEG latency of the same run is printed beside it:
the OSC latency is that plus the wait for the next frame (up to one frame
period) and the UDP hop.

    python -m benchmarks.osc_bench [--size 1280x720] [--rounds 40] [--fps 30]

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import copy
import json
import platform
import random
import statistics
import tempfile
import threading
import time
from pathlib import Path

import cv2
import numpy as np

from marblevideo.live.sources import Source, TestPattern

from .live_bench import RECIPE


class StillSource(Source):
    """One picture published at ``fps`` (a camera pointed at a still scene)."""

    name = "still"

    def __init__(self, rgba: np.ndarray, fps: float):
        super().__init__()
        self.rgba, self.fps = rgba, fps
        self.size = (rgba.shape[1], rgba.shape[0])

    def capture(self) -> None:
        period, next_at = 1.0 / self.fps, time.monotonic()
        while not self._stop.wait(max(0.0, next_at - time.monotonic())):
            self.publish(self.rgba.copy(), time.monotonic())
            next_at += period


def _jpeg_after(session, seq: int) -> tuple[int, np.ndarray, float]:
    seq, data, *_ = session.latest_jpeg(seq, 2.0)
    when = time.monotonic()
    if data is None:
        raise RuntimeError("no preview frame for 2 s")
    small = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_REDUCED_COLOR_4)  # cheap
    return seq, small.astype(np.int16), when


def _settle(session, client, value: float) -> np.ndarray:
    client.send_message("/swirl", value)
    time.sleep(0.5)
    return _jpeg_after(session, session.preview.seq)[1]


def rounds(session, client, n: int, fps: float) -> list[float]:
    """OSC send -> first JPEG showing the value, in ms, for ``n`` rounds."""
    refs = [_settle(session, client, 0.0), _settle(session, client, 1.0)]
    out, value = [], 1
    for _ in range(n):
        value = 1 - value
        time.sleep(0.15 + random.random() / fps)  # a random phase of the frame clock
        seq = session.preview.seq
        sent = time.monotonic()
        client.send_message("/swirl", float(value))
        while True:
            seq, jpeg, when = _jpeg_after(session, seq)
            near = [float(np.abs(jpeg - ref).mean()) for ref in refs]
            if near[value] < near[1 - value]:
                out.append((when - sent) * 1000)
                break
    return out


def bench(size: tuple[int, int], n: int, fps: float, device: str | None) -> dict:
    from pythonosc.udp_client import SimpleUDPClient

    from marblevideo.controllers.osc import OscListener
    from marblevideo.live.session import LiveSession

    recipe = copy.deepcopy(RECIPE)
    recipe["canvas"] = list(size)
    recipe["ops"][5]["alpha"] = {"signal": "osc:/swirl", "range": [0, 900]}
    picture = TestPattern(size, fps).frame(1.0, 0)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "osc.json"
        path.write_text(json.dumps(recipe))
        session = LiveSession(path, StillSource(picture, fps), device=device, jpeg=True, quiet=True)
        osc = OscListener(session.controllers, "127.0.0.1", 0).start()
        client = SimpleUDPClient("127.0.0.1", osc.port)
        result: dict = {}

        def drive():
            try:
                session.meters.clear()
                result["osc_ms"] = rounds(session, client, n, fps)
                result["stats"] = session.stats()
            finally:
                session.stop_event.set()

        threading.Timer(2.0, drive).start()  # after a warm-up
        try:
            session.run()
        finally:
            osc.close()
            session.close()
    ms = sorted(result["osc_ms"])
    stats = result["stats"]
    return {
        "size": f"{size[0]}x{size[1]}",
        "source_fps": fps,
        "rounds": len(ms),
        "osc_to_preview_median_ms": round(statistics.median(ms), 1),
        "osc_to_preview_p95_ms": round(ms[min(len(ms) - 1, int(0.95 * len(ms)))], 1),
        "osc_to_preview_max_ms": round(ms[-1], 1),
        "capture_to_jpeg_median_ms": stats["latency_ms"],
        "render_median_ms": stats["render_ms"],
        "fps": stats["fps"],
        "device": session.renderer.info.name,
        "machine": f"{platform.machine()} {platform.processor() or ''}".strip(),
    }


def main() -> None:
    from marblevideo.cli.arguments import parse_size

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size", default="1280x720")
    p.add_argument("--rounds", type=int, default=40)
    p.add_argument("--fps", type=float, default=30.0)
    p.add_argument("--device")
    args = p.parse_args()
    print(json.dumps(bench(parse_size(args.size), args.rounds, args.fps, args.device)))


if __name__ == "__main__":
    main()
