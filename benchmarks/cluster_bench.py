"""The benchmarks' ``cluster`` part: a 720p clip rendered whole, in segments one after
another in this process (each phase timed: plan, segments, join), and in
segments on a local Ray with 1 and 2 workers (the whole call: workers started,
programs built, segments rendered, joined)."""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

from marblevideo import api
from marblevideo.jobs.segments import join_segments, plan_segments
from marblevideo.media.encode import plan_output
from marblevideo.media.video import VideoOptions
from marblevideo.recipe import parse_recipe
from marblevideo.scale.cluster import RayPool, SerialPool, connect, require_ray
from marblevideo.scale.segmented import SegmentJob, render_segment, render_split

ENCODER = {"preset": "veryfast", "crf": 23}


def clocked(fn) -> tuple[float, object]:
    t = time.perf_counter()
    result = fn()
    return time.perf_counter() - t, result


def serial_phases(clip: Path, recipe, out: Path, segments: int) -> dict[str, float]:
    """Plan, each segment and the join, timed, on one renderer in this process."""
    took: dict[str, float] = {}
    took["plan"], parts = clocked(lambda: plan_segments(clip, segments))
    options = VideoOptions(**ENCODER, overwrite=True, quiet=True)
    plan = plan_output(out, options)
    job = SegmentJob(str(clip), recipe, {**ENCODER, "codec": plan.codec, "pix_fmt": plan.pix_fmt})
    pool = SerialPool()
    paths = [out.with_name(f"seg{s.index}.mp4") for s in parts]
    calls = [(job, s, str(p)) for s, p in zip(parts, paths, strict=True)]
    t = time.perf_counter()
    seconds = []
    for _ in pool.run(render_segment, calls):
        seconds.append(time.perf_counter() - t)
        t = time.perf_counter()
    took["segments"] = sum(seconds)
    took["slowest"] = max(seconds)
    pairs = [(p, s.origin) for p, s in zip(paths, parts, strict=True)]
    took["join"], _ = clocked(lambda: join_segments(clip, pairs, out, plan, options))
    return took


def cluster_part(device: str | None, make_clip, animated, seconds: int = 16) -> None:
    """Scaling from 1 to 2 workers on this machine (see the module)."""
    ray = require_ray()
    fps, segments, rounds = 30, 4, 2
    recipe = parse_recipe(animated(seconds), "animated12")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        clip = make_clip(tmp / "clip.mp4", seconds=seconds, fps=fps, keyint=2 * fps)
        out = tmp / "out.mp4"
        n = seconds * fps
        print(
            f"\n## On a cluster: 1280x720, {seconds} s ({n} frames), 12 ops RGSS animated, "
            f"x264 veryfast crf 23, {segments} segments; medians of {rounds} rounds"
        )
        api.render_video(clip, recipe, out, overwrite=True, quiet=True, **ENCODER)  # warm caches
        single = [
            clocked(
                lambda: api.render_video(
                    clip, recipe, out, overwrite=True, quiet=True, device=device, **ENCODER
                )
            )[0]  # fmt: skip
            for _ in range(rounds)
        ]
        s = statistics.median(single)
        print(f"single render, in process:          {s:6.2f} s ({n / s:5.1f} fps)")
        phases = [serial_phases(clip, recipe, out, segments) for _ in range(rounds)]
        med = {k: statistics.median(p[k] for p in phases) for k in phases[0]}
        whole = med["plan"] + med["segments"] + med["join"]
        print(
            f"in segments, serially, in process: {whole:6.2f} s: plan {med['plan']:.3f} s, "
            f"segments {med['segments']:.2f} s (slowest {med['slowest']:.2f}), "
            f"join {med['join']:.3f} s"
        )
        start, started = clocked(lambda: connect(ray))
        print(f"local Ray started:                  {start:6.2f} s")
        try:
            _ray_rows((clip, recipe, out), device, segments, rounds, (n, s))
        finally:
            if started:
                ray.shutdown()


def _ray_rows(job: tuple, device, segments: int, rounds: int, single: tuple) -> None:
    """cluster_part's rows for a local Ray (started) with 1 and 2 workers; ``job``:
    (clip, recipe, out); ``single``: (frames, the single render's seconds)."""
    clip, recipe, out = job
    n, s = single
    for jobs in (1, 2):
        up, pool = clocked(lambda: RayPool(jobs, device))  # noqa: B023
        up += clocked(pool.where)[0]
        pool.close()
        runs = [
            clocked(
                lambda: render_split(
                    clip,
                    recipe,
                    out,
                    cluster="ray",
                    jobs=jobs,  # noqa: B023
                    segments=segments,
                    overwrite=True,
                    quiet=True,
                    device=device,
                    **ENCODER,
                )
            )[0]  # fmt: skip
            for _ in range(rounds)
        ]
        r = statistics.median(runs)
        print(
            f"Ray, {jobs} worker(s) x {2 // jobs} PoCL thread(s): {r:6.2f} s "
            f"({n / r:5.1f} fps; {s / r:.2f}x the single render), of which "
            f"workers up {up:.2f} s"
        )
