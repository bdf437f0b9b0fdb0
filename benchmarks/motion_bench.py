"""The ``motion`` analysis (marblevideo.motion): time per frame of
:meth:`MotionTracker.see` at 1280x720, against decoding the same frames (the
baseline a file render pays anyway), side by side in one run.

Writes a SECONDS-long 1280x720 30 fps clip (x264, in a temporary folder) of two
textured discs moving over a textured background, then, in ROUNDS rounds,
decodes it to RGB frames (timing each decode) and feeds them to a fresh tracker
(timing each ``see``; the first frame, which has no flow, left out), feeds the
frames' decoded luma planes (:func:`~marblevideo.media.decode.frame_luma`, what a
file render's transform stage hands the analysis) to another, copied and all
decoded first, and as they are decoded (the decoder's own plane, rows padded,
still in the cache: what a render hands over), and times the
analysis' parts on the RGB frames. Prints medians and 95th percentiles in ms, the
machine, the CPU's flags and the load average. THREADS, where given, is set as
OpenCV's thread count first (default: OpenCV's own, one per core). Run from the
repository root: ``python -m benchmarks.motion_bench [SECONDS] [ROUNDS] [THREADS]``.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import av
import cv2
import numpy as np

from marblevideo.media.decode import frame_luma
from marblevideo.motion import MotionSpec, MotionTracker, luma
from marblevideo.motion.flow import Flow, moving, reach, reduce, reduction, regions

from .common import header

SIZE, FPS = (1280, 720), 30


def _texture(w: int, h: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    noise = cv2.GaussianBlur(rng.normal(0, 1, (h, w, 3)).astype(np.float32), (0, 0), 2.0)
    return np.clip(128 + noise * 60 / noise.std(), 0, 255).astype(np.uint8)


def frames(seconds: float):
    """The clip's RGB frames: two discs (diameters 120 and 200) crossing the frame."""
    w, h = SIZE
    ground, skin = _texture(w, h, 1), _texture(240, 240, 2)
    for n in range(round(seconds * FPS)):
        frame = ground.copy()
        t = n / FPS
        for d, x, y in ((120, 100 + 300 * t, 200), (200, w - 150 - 200 * t, 480 + 60 * np.sin(t))):
            x, y = int(x) % w, int(y)
            mask = np.zeros((h, w), np.uint8)
            cv2.circle(mask, (x, y), d // 2, 1, -1)
            shifted = np.roll(skin, (y % 240, x % 240), axis=(0, 1))
            tile = np.tile(shifted, (h // 240 + 1, w // 240 + 1, 1))[:h, :w]
            frame[mask > 0] = tile[mask > 0]
        yield frame


def write_clip(path: Path, seconds: float) -> None:
    with av.open(str(path), "w") as out:
        stream = out.add_stream("libx264", rate=FPS)
        stream.width, stream.height, stream.pix_fmt = *SIZE, "yuv420p"
        stream.options = {"preset": "veryfast", "crf": "18"}
        for image in frames(seconds):
            out.mux(stream.encode(av.VideoFrame.from_ndarray(image, format="rgb24")))
        out.mux(stream.encode())


def decoded(path: Path) -> tuple[list[np.ndarray], list[np.ndarray], list[float]]:
    """Every frame as RGB and its luma plane (copied), and each RGB decode's time in ms."""
    images, planes, times = [], [], []
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        stream.thread_type = "NONE"
        it = container.decode(stream)
        while True:
            began = time.perf_counter()
            try:
                frame = next(it)
            except StopIteration:
                break
            images.append(frame.to_ndarray(format="rgb24"))
            times.append((time.perf_counter() - began) * 1000)
            planes.append(np.array(frame_luma(frame)))
    return images, planes, times


def analysed(images: list[np.ndarray]) -> tuple[list[float], list[float], list[float], int]:
    """Each ``see``'s wall time, CPU time of all the process' threads and CPU time
    of the calling thread (its share of OpenCV's parallel work, the rest running
    beside it on the other core) in ms, the first frame left out, and the strokes made."""
    tracker = MotionTracker(MotionSpec(), (1.0, 1.0, 0.0, 0.0))
    wall, cpu, own = [], [], []
    for n, image in enumerate(images):
        began, used, mine = time.perf_counter(), time.process_time(), time.thread_time()
        tracker.see(image, n / FPS)
        wall.append((time.perf_counter() - began) * 1000)
        cpu.append((time.process_time() - used) * 1000)
        own.append((time.thread_time() - mine) * 1000)
    return wall[1:], cpu[1:], own[1:], len(tracker.take())


def parts(images: list[np.ndarray]) -> dict[str, list[float]]:
    """The analysis' steps timed apart, ms per frame."""
    flow, k = Flow(), reduction(*SIZE)
    scale = (k * FPS, k * FPS)
    low = reach(scale, 60.0)
    out: dict[str, list[float]] = {"luma": [], "reduce": [], "DIS + seed": [], "regions": []}
    for image in images:
        t0 = time.perf_counter()
        gray = luma(image)
        t1 = time.perf_counter()
        small = reduce(gray, k)
        t2 = time.perf_counter()
        motion = flow.step(small, low)
        t3 = time.perf_counter()
        if motion is None:
            continue
        regions(moving(motion, scale, 60.0), k)
        t4 = time.perf_counter()
        for name, a, b in zip(out, (t0, t1, t2, t3), (t1, t2, t3, t4), strict=True):
            out[name].append((b - a) * 1000)
    return out


def as_decoded(path: Path) -> list[float]:
    """CPU time in ms of each ``see`` (the first left out) of each frame's luma
    plane as the decoder wrote it (a view, rows padded), handed over as soon as
    decoded, as a file render's transform stage takes it."""
    tracker = MotionTracker(MotionSpec(), (1.0, 1.0, 0.0, 0.0))
    cpu = []
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        stream.thread_type = "NONE"
        for n, frame in enumerate(container.decode(stream)):
            plane = frame_luma(frame)
            used = time.process_time()
            tracker.see(plane, n / FPS)
            cpu.append((time.process_time() - used) * 1000)
    return cpu[1:]


def _row(name: str, times: list[float]) -> str:
    p95 = float(np.percentile(times, 95))
    return f"| {name} | {statistics.median(times):.2f} | {p95:.2f} | {len(times)} |"


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    if len(sys.argv) > 3:
        cv2.setNumThreads(int(sys.argv[3]))
    header()
    print(f"# OpenCV {cv2.__version__}, {cv2.getNumThreads()} threads; load average before: "
          + " ".join(f"{x:.2f}" for x in os.getloadavg()))  # fmt: skip
    decode, see, cpu, see_y, cpu_y, own_y, steps, strokes = [], [], [], [], [], [], {}, 0
    fresh: list[float] = []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "clip.mp4"
        write_clip(path, seconds)
        for _ in range(rounds):
            images, planes, took = decoded(path)
            decode += took
            fresh += as_decoded(path)
            took, used, own, strokes = analysed(planes)
            see_y, cpu_y, own_y = see_y + took, cpu_y + used, own_y + own
            took, used, _, _ = analysed(images)
            see += took
            cpu += used
            for name, values in parts(images).items():
                steps.setdefault(name, []).extend(values)
    print(f"1280x720 {FPS} fps, {seconds:g} s, {rounds} rounds; {strokes} strokes a round")
    print("| per frame | median ms | p95 ms | frames |")
    print("|---|---|---|---|")
    print(_row("decode to RGB (baseline)", decode))
    print(_row("MotionTracker.see, luma plane (a file render's)", see_y))
    print(_row("MotionTracker.see, luma plane, CPU time (all threads)", cpu_y))
    print(_row("MotionTracker.see, luma plane, CPU time (calling thread)", own_y))
    print(_row("MotionTracker.see, luma plane as decoded, CPU time (all threads)", fresh))
    print(_row("MotionTracker.see, RGB", see))
    print(_row("MotionTracker.see, RGB, CPU time (all threads)", cpu))
    for name, values in steps.items():
        print(_row(f"  {name}", values))
    print("# load average after: " + " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
