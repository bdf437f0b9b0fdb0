"""Whole commands: the CLI marbling a 720p clip against a plain PyAV transcode
(e2e), what any sampling scheme can reach (bounds), and peak RSS (memory)."""

from __future__ import annotations

import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import av

from .common import ENV, PLAIN_SCRIPT, animated12, make_clip, marble_command, recipe12, turn12
from .plain_transcode import plain_transcode


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
        times = paired_rounds(cmds, (clip, tmp / "plain.mp4"))
    print(f"\n## End to end: 1280x720, {seconds} s ({n} frames), 12 ops RGSS, x264 veryfast crf 23")
    _e2e_report(times, list(recipes), n, fixed_end, fixed_frames)


def paired_rounds(cmds: dict[str, list[str]], plain=None, rounds: int = 5) -> dict:
    """Seconds of each command (name -> list) over ``rounds`` rounds, each round
    running every command once, so that ratios are paired; ``plain``: (clip, out),
    the in-process plain transcode timed first in each round as "plain"."""
    times: dict[str, list[float]] = {**({"plain": []} if plain else {}), **{k: [] for k in cmds}}
    for _ in range(rounds):
        if plain:
            t = time.perf_counter()
            plain_transcode(*plain)
            times["plain"].append(time.perf_counter() - t)
        for name, cmd in cmds.items():
            t = time.perf_counter()
            subprocess.run(cmd, check=True, env=ENV)
            times[name].append(time.perf_counter() - t)
    return times


def _e2e_report(times: dict, names: list[str], n: int, fixed_end: float, fixed_frames: int):
    """e2e's lines: the transcode's, the CLI's fixed cost, each recipe's two ratios."""
    med = {k: statistics.median(v) for k, v in times.items()}
    p = med["plain"]
    print(f"plain PyAV decode+encode, in process: {p:.2f} s ({p / n * 1e3:.1f} ms/frame)")
    print(f"the same as a script (its own process): {med['script']:.2f} s")
    fixed = med["fixed"]
    print(f"CLI fixed cost (start, set-up, first frames; --end {fixed_end}): {fixed:.2f} s")
    rounds = list(zip(times["plain"], times["script"], times["fixed"], strict=True))
    for name in names:
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
        times = paired_rounds(cmds)
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
