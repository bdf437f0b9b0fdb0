"""Soak benchmark of ``marblevideo live --preview``: a long session as a user runs it.

The real command in a subprocess: the test pattern at 1280x720, 30 fps -> the
animated 6-op recipe of live_bench.py (RGSS) -> the designer's page in live mode
open in headless Chromium (Playwright; it draws every new ``/frame.jpg`` and
polls ``/stats``, as a user's browser does) -> a recording (``-o soak.mp4``).
Every ``--edit-every`` seconds another program saves the recipe (a temporary
file renamed over it, as editors save) with one number changed: the session
reloads it and the page follows.

Sampled every 5 s: the session's frames and recipe version (``/stats``), the
page's frames and version, and the command's resident memory (VmRSS of
/proc/PID/status; Chromium's own is not counted). Reported: per-minute frame
rate of the session and of the page, RSS per minute and its growth after the
warm-up (the first minute: kernels built, buffers allocated, caches filled) as
last minus first sample and as the slope of a least-squares line, the reloads
the session and the page took against the edits made, and the recording's
duration and frame count (PyAV) against the session's.

    python -m benchmarks.soak_bench [--minutes 10] [--size 1280x720]
        [--edit-every 15] [--out soak.json] [--trace] [--motion]

``--motion``: the source is the looped clip of six discs going round
(:mod:`benchmarks.motion_clip`) and the recipe the ``dance`` preset (motion);
each edit changes a wave and the motion's gain. Sampled besides (``GET
/api/motion``): the motion strokes rendered, their points, and the ops walked
per frame (the recipe's and the strokes), which must stay bounded (strokes heal
``memory`` + ``heal`` seconds after their last point).

``--trace`` runs the same session in this process with a client thread in
place of the browser and compares tracemalloc snapshots taken after the
warm-up and at the end: whether the Python heap grows, against the RSS.

Not a test: numbers depend on the machine and its load (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .common import ENV
from .live_bench import RECIPE

SAMPLE = 5.0
WARMUP = 60.0


def rss_mb(pid: int) -> float:
    """Resident memory of process ``pid`` in MB (VmRSS)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError(f"no VmRSS for {pid}")


def dance() -> dict:
    """The ``dance`` preset's recipe (the motion soak's)."""
    from marblevideo.bundled import presets

    return json.loads(presets()["dance"].read_text())


def edited(n: int, motion: bool = False) -> dict:
    """The recipe's ``n``-th edit: the comb's strength and the drop's radius moved
    (``motion``: the first wave's wavelength and the motion's gain)."""
    if motion:
        doc = dance()
        doc["ops"][0]["wavelength"] = 380 + 20 * (n % 5)
        doc["motion"]["gain"] = 1.0 + 0.25 * (n % 4)
        return doc
    doc = copy.deepcopy(RECIPE)
    doc["ops"][1]["alpha"] = 40 + 10 * (n % 5)
    doc["ops"][0]["radius"] = 100 + 5 * (n % 7)
    return doc


def save(path: Path, doc: dict) -> None:
    """Save as an editor does: a temporary file beside ``path``, renamed over it."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(json.dumps(doc, indent=1))
    os.replace(tmp, path)


def start_live(
    folder: Path, size: str, seconds: float, motion: bool = False
) -> tuple[subprocess.Popen, str]:
    recipe = folder / "soak-recipe.json"
    save(recipe, dance() if motion else RECIPE)
    source = ["test", "--size", size]
    if motion:
        from .motion_clip import six_discs

        w, h = map(int, size.split("x"))
        source = [str(six_discs(size=(w, h))), "--loop"]
    cmd = [
        sys.executable, "-m", "marblevideo", "live", *source,
        "--ops", str(recipe), "--preview", "--port", "0", "-o", str(folder / "soak.mp4"),
        "--duration", str(seconds),
    ]  # fmt: skip
    env = ENV
    log = (folder / "live.stderr").open("w")  # noqa: SIM115 - the child writes it to the end
    proc = subprocess.Popen(cmd, cwd=folder, env=env, stdout=subprocess.PIPE, stderr=log)
    line = proc.stdout.readline().decode()
    if not line.startswith("preview: "):
        proc.kill()
        raise RuntimeError(f"no preview URL: {line!r} {(folder / 'live.stderr').read_text()}")
    return proc, line.split(" ", 1)[1].strip()


def get_json(url: str) -> dict:
    import urllib.request

    with urllib.request.urlopen(url, timeout=10) as r:
        return json.loads(r.read())


def page_state(page) -> dict:
    return page.evaluate(
        "({frames: Number(document.getElementById('sheet').dataset.frames || 0), "
        "version: designer.state.version})"
    )


def soak(
    folder: Path, page, proc, url: str, minutes: float, edit_every: float, motion: bool = False
) -> list[dict]:
    """Sample every SAMPLE seconds for ``minutes``, saving an edit every ``edit_every``."""
    recipe = folder / "soak-recipe.json"
    samples, edits = [], 0
    start = time.monotonic()
    next_edit = start + edit_every
    while (now := time.monotonic()) - start < minutes * 60:
        if now >= next_edit:
            edits += 1
            save(recipe, edited(edits, motion))
            next_edit += edit_every
        stats = get_json(url + "stats")
        shown = page_state(page)
        moved = get_json(url + "api/motion") if motion else {"strokes": []}
        samples.append(
            {
                "t": round(now - start, 2),
                "frames": stats["frames"],
                "fps": stats["fps"],
                "latency_ms": stats["latency_ms"],
                "recorded": stats["recorded"],
                "record_dropped": stats["record_dropped"],
                "version": stats["recipe_version"],
                "error": stats["recipe_error"],
                "page_frames": shown["frames"],
                "page_version": shown["version"],
                "rss_mb": round(rss_mb(proc.pid), 1),
                "edits": edits,
                "motion_strokes": len(moved["strokes"]),
                "motion_points": sum(len(op["points"]) for op in moved["strokes"]),
                "ops_per_frame": len(get_json(url + "api/recipe")["ops"]) + len(moved["strokes"]),
            }
        )
        time.sleep(max(0.0, start + len(samples) * SAMPLE - time.monotonic()))
    return samples


def per_minute(samples: list[dict]) -> list[dict]:
    """Frame rates (session, page) and RSS at the end of each whole minute."""
    rows, prev = [], samples[0]
    for s in samples[1:]:
        if int(s["t"] // 60) > int(prev["t"] // 60) or s is samples[-1]:
            dt = s["t"] - prev["t"]
            rows.append(
                {
                    "minute": round(s["t"] / 60, 1),
                    "fps": round((s["frames"] - prev["frames"]) / dt, 1),
                    "page_fps": round((s["page_frames"] - prev["page_frames"]) / dt, 1),
                    "latency_ms": s["latency_ms"],
                    "rss_mb": s["rss_mb"],
                    "ops_per_frame": s["ops_per_frame"],
                    "motion_points": s["motion_points"],
                }
            )
            prev = s
    return rows


def slope(points: list[tuple[float, float]]) -> float:
    """Least-squares slope of (x, y) points."""
    n = len(points)
    mx = sum(x for x, _ in points) / n
    my = sum(y for _, y in points) / n
    sxx = sum((x - mx) ** 2 for x, _ in points)
    return sum((x - mx) * (y - my) for x, y in points) / sxx if sxx else 0.0


def recording(path: Path) -> dict:
    import av

    with av.open(str(path)) as c:
        stream = c.streams.video[0]
        pts = [f.pts for f in c.decode(stream)]
        tb = float(stream.time_base)
    return {"frames": len(pts), "seconds": round((pts[-1] - pts[0]) * tb, 2) if pts else 0.0}


def session_summary(stderr: str) -> dict:
    """The session's own last words: its length and how many frames it recorded."""
    import re

    line = [x for x in stderr.splitlines() if " frames in " in x][-1]
    seconds = float(re.search(r" in ([\d.]+) s", line).group(1))
    recorded = int(re.search(r"recorded (\d+)", line).group(1))
    return {"session_seconds": seconds, "recorded_frames_session": recorded, "summary": line}


def summary(samples, rec, edits) -> dict:
    warm = [s for s in samples if s["t"] >= WARMUP]
    last = samples[-1]
    return {
        "minutes": round(last["t"] / 60, 2),
        "per_minute": per_minute(samples),
        "rss_start_mb": samples[0]["rss_mb"],
        "rss_after_warmup_mb": warm[0]["rss_mb"],
        "rss_end_mb": last["rss_mb"],
        "rss_growth_after_warmup_mb": round(last["rss_mb"] - warm[0]["rss_mb"], 1),
        "rss_max_mb": max(s["rss_mb"] for s in warm),
        "rss_slope_mb_per_min": round(60 * slope([(s["t"], s["rss_mb"]) for s in warm]), 2),
        "edits": edits,
        "reloads": last["version"] - 1,
        "page_reloads": last["page_version"] - samples[0]["page_version"],
        "recipe_errors": sorted({s["error"] for s in samples if s["error"]}),
        "record_dropped": last["record_dropped"],
        "ops_per_frame_range": [
            min(x["ops_per_frame"] for x in samples),
            max(x["ops_per_frame"] for x in samples),
        ],
        "motion_points_max": max(x["motion_points"] for x in samples),
        "recording": rec,
    }


def markdown(result: dict) -> str:
    lines = [
        "| minute | session fps | page fps | latency ms | RSS MB | ops per frame | stroke points |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in result["per_minute"]:
        lines.append(
            f"| {r['minute']} | {r['fps']} | {r['page_fps']} | {r['latency_ms']} | {r['rss_mb']} "
            f"| {r['ops_per_frame']} | {r['motion_points']} |"
        )
    return "\n".join(lines)


def run(args) -> dict:
    from playwright.sync_api import sync_playwright

    chromium = os.environ.get("MARBLEVIDEO_CHROMIUM") or shutil.which("chromium")
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        folder = Path(tmp)
        proc, url = start_live(folder, args.size, args.minutes * 60 + 120, args.motion)
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        try:
            page = browser.new_page(viewport={"width": 1300, "height": 900})
            page.goto(url)
            page.wait_for_selector("body[data-ready='1'][data-mode='live']", timeout=60000)
            samples = soak(folder, page, proc, url, args.minutes, args.edit_every, args.motion)
        finally:
            browser.close()
            proc.send_signal(signal.SIGINT)
            rc = proc.wait(120)
        if rc != 0:
            raise RuntimeError(f"live exited {rc}: {(folder / 'live.stderr').read_text()}")
        result = summary(samples, recording(folder / "soak.mp4"), samples[-1]["edits"])
        result.update(session_summary((folder / "live.stderr").read_text()))
    result["samples"] = samples
    return result


def _fetcher(url: str, stop) -> None:
    """A client as the page is: each new /frame.jpg, then /stats."""
    import urllib.request

    seq = 0
    while not stop.is_set():
        try:
            with urllib.request.urlopen(f"{url}frame.jpg?after={seq}", timeout=5) as r:
                r.read()
                seq = int(r.headers["X-Frame-Seq"])
            get_json(url + "stats")
        except OSError:
            time.sleep(0.1)


def trace(args) -> dict:
    """``--trace``: the same session in this process, a client thread in place of
    the browser, and tracemalloc snapshots after the warm-up and at the end: how
    much the Python heap grew (and where) against the process's RSS."""
    import threading
    import tracemalloc

    from marblevideo.cli.live import build_parser, recorder_for
    from marblevideo.design.live import LiveDesign
    from marblevideo.live.session import LiveSession
    from marblevideo.live.sources import TestPattern
    from marblevideo.serve.server import Server

    tracemalloc.start(10)
    w, h = map(int, args.size.split("x"))
    with tempfile.TemporaryDirectory() as tmp:
        recipe = Path(tmp) / "soak-recipe.json"
        save(recipe, RECIPE)
        session = LiveSession(recipe, TestPattern((w, h), 30), jpeg=True, quiet=True)
        recording = f"{tmp}/soak.mp4"
        opts = build_parser().parse_args(["--ops", str(recipe), "-o", recording, "-y"])
        session.recorder = recorder_for(opts, recording)
        session.recorder.start(w, h, 30)
        server = Server(LiveDesign(session), 0)
        server.start()
        stop, marks = threading.Event(), []

        def drive() -> None:
            start, n = time.monotonic(), 0
            while time.monotonic() - start < args.minutes * 60:
                time.sleep(args.edit_every)
                n += 1
                save(recipe, edited(n))
                if not marks and time.monotonic() - start >= WARMUP:
                    marks.append((tracemalloc.take_snapshot(), rss_mb(os.getpid())))
            marks.append((tracemalloc.take_snapshot(), rss_mb(os.getpid())))
            session.stop_event.set()

        threading.Thread(target=_fetcher, args=(server.url, stop), daemon=True).start()
        threading.Thread(target=drive, daemon=True).start()
        try:
            session.run()
        finally:
            stop.set()
            server.stop()
            session.close()
            session.recorder.close()
    (a, rss_a), (b, rss_b) = marks[0], marks[-1]
    heap = [sum(x.size for x in snap.statistics("filename")) / 2**20 for snap in (a, b)]
    return {
        "rss_mb": [round(rss_a, 1), round(rss_b, 1)],
        "python_heap_mb": [round(x, 2) for x in heap],
        "frames": session.frames,
        "top_growth": [str(x) for x in b.compare_to(a, "lineno")[:5]],
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--minutes", type=float, default=10.0)
    p.add_argument("--size", default="1280x720")
    p.add_argument("--edit-every", type=float, default=15.0, help="seconds between edits")
    p.add_argument("--out", help="write every sample and the summary to this JSON file")
    p.add_argument(
        "--trace", action="store_true", help="in this process, no browser: Python heap vs RSS"
    )
    p.add_argument(
        "--motion", action="store_true", help="six discs going round through the dance preset"
    )
    args = p.parse_args()
    if args.trace:
        print(json.dumps(trace(args), indent=1))
        return
    result = run(args)
    result["machine"] = f"{platform.machine()} {platform.processor() or ''}".strip()
    if args.out:
        Path(args.out).write_text(json.dumps(result, indent=1))
    print(markdown(result))
    print(json.dumps({k: v for k, v in result.items() if k not in ("samples", "per_minute")}))


if __name__ == "__main__":
    main()
