"""Benchmark of the designer in real time: frames per second, latency
from a pointer move to the frame that shows it, and agreement of mid-gesture
frames with the exact render, during every gesture, in a real headless Chromium.

Runs the real ``marblevideo design`` (a subprocess on 127.0.0.1) on each design
(``nonpareil`` and ``bouquet``: working copies of the presets; ``64ops``: a
1024x768 design of 64 mixed ops, realtime_probe.design64) and drives the page
with the mouse at a human pace (--rate moves per second for --seconds; sent
through Playwright's CDP session without waiting for each move, see Pointer):
a drop dragged open, a comb dragged across, a stroke drawn, a handle of the top
op dragged round three quarters of a circle (Alt held) and a slider of the top
op swept. Each gesture is undone after it. What is measured (benchmarks/realtime_probe.py says how):

- fps: frames drawn on the sheet per second between the first and last move;
- latency: per input, from the move to the first frame answering it (median,
  p95; ``never``: inputs no frame answered before the hand stopped);
- agree: after the last move (the button still held), the share of the sheet's
  pixels within 8 levels of the server's exact render of what that frame shows
  (``POST /api/frame.rgba`` at its size, view and time; --verify: also the
  settled sheet's, which should be ~100%);
- up->exact: from letting go to the first exact frame after it;
- stages_ms (in --json): the median page time of a warped frame's stages
  (``marbleFrames`` ``ms``: the draw issued; then read back and put on the 2D
  sheet, or with the WebGL canvas shown, sheetgl.js, only shown).

A frame shown on the WebGL canvas counts as drawn when a fence says its draw is
done (at an animation frame), so fps and latency include SwiftShader's work.

Where the page records the frames and the inputs they answer
(``window.marbleFrames``), those are read; else the sheet's frame counter stands in (the frame
answering the newest input at its render's start). ``--live`` measures
``marblevideo live test --preview`` at 1280x720 while a comb is dragged and a
stroke drawn (--live-tools): the gesture goes to the session as a preview, and
a live frame answers the input its preview was made after, the first time a
frame shows that preview (its ``X-Preview-Serial``), so the latency is from a
pointer move to the live frame that shows it; up->live: from letting go to the second live frame
asked for after the save (the first may have been marbled before it).

    python -m benchmarks.designer_realtime [--design nonpareil bouquet 64ops]
        [--repeat 1] [--dpr 1] [--viewport 1280x860] [--live] [--json out.json]
        [--query glsheet=0]

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .common import ENV, cpu_summary, header
from .realtime_probe import PROBE, agree, compare, design64, figures, table

GESTURES = ("drop", "comb", "stroke", "handle", "slider")
LIVE_RECIPE = {"marblevideo": 1, "canvas": [1280, 720], "antialias": "rgss", "ops": [
    {"type": "drop", "center": [640, 360], "radius": 160, "color": "#1d4e89"},
    {"type": "drop", "center": [640, 360], "radius": 80, "color": "#e9c46a"}]}  # fmt: skip


def serve(tmp: Path, design: str, live: bool = False, fps: float | None = None):
    """The designer (or live --preview, its source at ``fps``: the test pattern's
    30 by default) serving ``design``: (process, url)."""
    if design == "64ops":
        (tmp / "design64.json").write_text(json.dumps(design64()))
        design = "design64.json"
    elif design == "live":
        (tmp / "live.json").write_text(json.dumps(LIVE_RECIPE))
        design = "live.json"
    cmd = [sys.executable, "-m", "marblevideo"]
    cmd += (
        ["live", "test", "--size", "1280x720", "--preview"] if live else ["design", "--no-browser"]
    )
    cmd += ["--ops", design, "--port", "0", "-q"] + (["--fps", str(fps)] if fps else [])
    proc = subprocess.Popen(cmd, cwd=tmp, env=ENV, stdout=subprocess.PIPE, text=True)
    for line in proc.stdout:
        if "http://" in line:
            return proc, line[line.index("http://") :].strip().rstrip("/") + "/"
    raise RuntimeError(f"{' '.join(cmd)}: no URL printed (exit {proc.wait()})")


def settle(page, quiet_ms: int = 700, limit: float = 30) -> None:
    """Wait until the newest frame is exact, none was drawn for ``quiet_ms`` and no
    save or server frame is on its way (``designer.rendering``, where the page
    has it: an undo's frames no longer run into the next gesture; at most
    ``limit`` seconds)."""
    end = time.time() + limit
    while time.time() < end:
        state = page.evaluate(
            """() => { const B = benchProbe, f = B.frames.at(-1), g = B.pageFrames.at(-1);
              const last = Array.isArray(window.marbleFrames) ? g : f;
              return {idle: performance.now() - (last ? last.drawnAt : 0), kind: last && last.kind,
                      saving: designer.state.saving || !!designer.rendering?.()}; }"""
        )
        if state["idle"] >= quiet_ms and not state["saving"] and state["kind"] in ("exact", None):
            return
        time.sleep(0.1)


def to_client(page, point) -> tuple[float, float]:
    """A canvas point -> client coordinates on the sheet (the frame fills it)."""
    return tuple(
        page.evaluate(
            """([x, y]) => { const i = designer.state.info, r = document.getElementById('sheet')
              .getBoundingClientRect();
              return [r.left + (i.scale * x + i.offset[0]) / i.size[0] * r.width,
                      r.top + (i.scale * y + i.offset[1]) / i.size[1] * r.height]; }""",
            list(point),
        )
    )


def path_of(page, gesture: str, n: int):
    """The client points of ``gesture`` (n moves) and how to start it: (points, mode, keys)."""
    r = page.locator("#sheet").bounding_box()
    at = lambda fx, fy: (r["x"] + fx * r["width"], r["y"] + fy * r["height"])  # noqa: E731
    ks = [k / (n - 1) for k in range(n)]
    if gesture == "drop":
        return [at(0.5 + 0.22 * s * math.cos(2 * s), 0.5 + 0.22 * s * math.sin(2 * s)) for s in ks]
    if gesture == "comb":
        return [at(0.15 + 0.7 * s, 0.45 + 0.08 * math.sin(6 * s)) for s in ks]
    if gesture == "stroke":
        return [at(0.15 + 0.7 * s, 0.5 + 0.25 * math.sin(2 * math.pi * s)) for s in ks]
    count = page.evaluate("designer.state.doc.ops.length")
    if gesture == "handle":
        for i in reversed(range(count)):
            inside = [
                to_client(page, p)
                for _, p in page.evaluate(f"designer.handles({i})")
                if isinstance(p[0], (int, float))
            ]
            inside = [(x, y) for x, y in inside if r["x"] + 20 < x < r["x"] + r["width"] - 20
                      and r["y"] + 20 < y < r["y"] + r["height"] - 20]  # fmt: skip
            if inside:
                page.evaluate(f"designer.store.update(() => ({{selected: {i}}}))")
                (x0, y0), rad = inside[0], 0.06 * r["width"]
                turn = 1.5 * math.pi  # three quarters of a circle: it ends away from the start
                return [
                    (x0 + rad * math.sin(turn * s), y0 + rad * (1 - math.cos(turn * s))) for s in ks
                ]
        raise RuntimeError("no op has a handle inside the sheet")
    page.evaluate(f"designer.store.update(() => ({{selected: {count - 1}}}))")
    slider = page.locator("#params input[type=range]").first
    slider.scroll_into_view_if_needed()
    box = slider.bounding_box()
    value = page.evaluate(
        """() => { const e = document.querySelector('#params input[type=range]');
          return (e.value - e.min) / (e.max - e.min); }"""
    )
    x0, y = box["x"] + 8 + value * (box["width"] - 16), box["y"] + box["height"] / 2
    span = 0.8 * (box["x"] + box["width"] - 8 - x0 if value < 0.5 else box["x"] + 8 - x0)
    return [(x0 + span * s, y) for s in ks]  # one way: the last move changes the value


class Pointer:
    """The mouse as a hand moves it: events sent through the page's CDP session at
    their times without waiting for the page to take each (Playwright's mouse.move
    waits, which paces the hand to the page's frames); the browser queues and
    coalesces them as it does real input. ``alt``: Alt held (a handle drag)."""

    def __init__(self, page):
        self.page, self.cdp, self.tasks = page, page.context.new_cdp_session(page), []

    def send(self, kind: str, at, buttons: int, alt: bool, last: bool = False) -> None:
        params = {"type": kind, "x": at[0], "y": at[1], "button": "left", "buttons": buttons}
        params.update(modifiers=1 if alt else 0, clickCount=0 if kind == "mouseMoved" else 1)
        if last:
            params["twist"] = 7  # the probe arms the input this move makes
        coro = self.cdp._impl_obj.send("Input.dispatchMouseEvent", params, None)
        self.tasks.append(self.cdp._loop.create_task(coro))

    def drag(self, points, rate: float, alt: bool = False, hold: float = 0.0) -> None:
        """Press at points[0], move through the rest at ``rate`` per second (and
        wait until the browser took them all), then ``hold`` seconds; the button stays down."""
        self.send("mouseMoved", points[0], 0, alt)
        self.send("mousePressed", points[0], 1, alt)
        t0 = time.perf_counter()
        for k, p in enumerate(points[1:], 1):
            rest = t0 + k / rate - time.perf_counter()
            if rest > 0:
                self.page.wait_for_timeout(rest * 1000)  # runs the sends meanwhile
            self.send("mouseMoved", p, 1, alt, last=k == len(points) - 1)
        while not all(t.done() for t in self.tasks):
            self.page.wait_for_timeout(5)
        self.tasks = []
        if hold:
            self.page.wait_for_timeout(hold * 1000)
        self.end = points[-1]

    def up(self, alt: bool = False) -> None:
        self.cdp.send("Input.dispatchMouseEvent", {"type": "mouseReleased", "x": self.end[0],
                      "y": self.end[1], "button": "left", "buttons": 0, "clickCount": 1,
                      "modifiers": 1 if alt else 0})  # fmt: skip


RESET = """(mode) => { const B = benchProbe; B.inputs = []; B.frames = []; B.pageFrames = [];
  B.snap = null; B.armSeq = null; B.armNext = false; B.puts = []; B.mode = mode;
  B.source = Array.isArray(window.marbleFrames) ? 'page' : 'counter'; }"""
READ = """() => { const B = benchProbe, s = B.snap; B.fresh();
  return {inputs: B.inputs, frames: B.frames, pageFrames: B.pageFrames, source: B.source,
          puts: B.puts, snap: s && {frame: s.frame, shown: s.shown}}; }"""


def timed_gesture(page, url, gesture: str, seconds: float, rate: float, verify=False, pause=0.0):
    """One gesture, timed: its figures, agreement and up->exact (``verify``: and the
    agreement of the sheet settled after it with the exact render of what it shows;
    ``pause``: seconds from selecting the op to pressing, for a handle or slider)."""
    if gesture in ("drop", "comb", "stroke"):
        page.evaluate(f"designer.setTool({json.dumps(gesture)})")
    points = path_of(page, gesture, max(2, int(seconds * rate)))
    if pause and gesture in ("handle", "slider"):
        page.wait_for_timeout(pause * 1000)  # a hand's pause from selecting to pressing
    page.evaluate(RESET, "slider" if gesture == "slider" else "pointer")
    began = page.evaluate("performance.now()")
    pointer, alt = Pointer(page), gesture == "handle"
    pointer.drag(points, rate, alt)
    with contextlib.suppress(Exception):
        page.wait_for_function("benchProbe.snap !== null", timeout=10000)
    probe = page.evaluate(READ)
    pixels = page.evaluate("benchProbe.snapPixels()")
    up = page.evaluate("performance.now()")
    pointer.up(alt)
    settle(page)
    after = page.evaluate(
        "benchProbe.source === 'page' ? benchProbe.pageFrames : benchProbe.frames"
    )
    exact = [f["drawnAt"] - up for f in after if f["kind"] == "exact" and f["drawnAt"] > up]
    result = {
        "gesture": gesture,
        **figures(probe),
        "up_to_exact_ms": round(exact[0]) if exact else None,
        "stages_ms": stages(page, began, up),
    }
    result.update(agree(url, probe["snap"], pixels))
    if verify:  # the comparison itself: the settled sheet against the exact render
        pixels = page.evaluate("benchProbe.snapPixels(true)")
        snap = page.evaluate("({frame: benchProbe.snap.frame, shown: benchProbe.snap.shown})")
        result["settled_agree"] = agree(url, snap, pixels)["agree"]
    page.evaluate("document.activeElement && document.activeElement.blur()")
    page.keyboard.press("Control+z")  # the design as it was for the next gesture
    settle(page)
    return result


def stages(page, began: float, up: float) -> list[float] | None:
    """Median ms of the warp frames' stages in the page between ``began`` and ``up``
    (``marbleFrames`` ``ms``: draw issued, read back, put on the sheet), or None."""
    ms = page.evaluate(
        "([a, b]) => (window.marbleFrames || []).filter((f) => f.ms && f.drawnAt > a"
        " && f.drawnAt < b).map((f) => f.ms)",
        [began, up],
    )
    if not ms:
        return None
    return [round(sorted(m[i] for m in ms)[len(ms) // 2], 1) for i in range(len(ms[0]))]


def open_page(p, url: str, viewport: tuple[int, int], dpr: float, live: bool = False):
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    browser = p.chromium.launch(
        executable_path=chromium, args=["--no-sandbox", "--enable-unsafe-swiftshader"]
    )
    context = browser.new_context(
        viewport={"width": viewport[0], "height": viewport[1]}, device_scale_factor=dpr
    )
    context.add_init_script(PROBE)
    page = context.new_page()
    page.goto(url)
    page.wait_for_selector("body[data-ready='1']", timeout=120000)
    page.wait_for_function(
        "benchProbe.frames.length > 0 || benchProbe.pageFrames.length > 0", timeout=120000
    )
    if live:  # the live frames never stop
        time.sleep(2)
    else:
        settle(page, 1000)
    return browser, page


@contextlib.contextmanager
def served_page(name: str, args, live: bool = False, fps: float | None = None):
    """``marblevideo design`` (or ``live test --preview``) on ``name`` in a
    temporary folder and its page in Chromium: yields (url, page)."""
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as folder, sync_playwright() as p:
        proc, url = serve(Path(folder), name, live=live, fps=fps)
        try:
            query = getattr(args, "query", None)
            page_url = url + ("?" + query if query else "")
            browser, page = open_page(p, page_url, args.viewport, args.dpr, live=live)
            yield url, page
            browser.close()
        finally:
            proc.terminate()
            proc.wait(30)


def kept(rows: list[dict], row: dict) -> None:
    """``row`` printed as it comes (stderr, JSON) and kept."""
    print(json.dumps(row), file=sys.stderr, flush=True)
    rows.append(row)


def bench_design(design: str, args) -> list[dict]:
    rows: list[dict] = []
    with served_page(design, args) as (url, page):
        timed_gesture(page, url, "comb", 0.5, args.rate)  # warm up: builds, first renders
        for run in range(args.repeat):
            for g in args.gestures:
                row = {"design": design, "run": run + 1, "load": os.getloadavg()[0]}
                row["pause_s"] = args.pause
                row.update(
                    timed_gesture(page, url, g, args.seconds, args.rate, args.verify, args.pause)
                )
                kept(rows, row)
    return rows


def live_gesture(page, tool: str, args) -> dict:
    """One drag of ``tool`` over the live frames, timed; then undone."""
    page.evaluate(f"designer.setTool({json.dumps(tool)})")
    points = path_of(page, tool, max(2, int(args.seconds * args.rate)))
    page.evaluate(RESET, "pointer")
    pointer = Pointer(page)
    pointer.drag(points, args.rate, hold=0.5)
    up = page.evaluate("performance.now()")
    pointer.up()
    time.sleep(3)
    probe = page.evaluate(READ)
    row = {"design": "live 1280x720", "gesture": f"{tool} (live)", **figures(probe)}
    # what the live frame shows once saved: from letting go to the second live frame
    # asked for after the save's answer (the first may have been marbled before it)
    puts = [q["end"] for q in probe["puts"] if q["start"] >= up - 1]
    fetched = [f for f in probe["frames"] if f.get("fetchedAt") is not None]
    later = [f["drawnAt"] for f in fetched if puts and f["fetchedAt"] >= puts[0]]
    row["up_to_live_ms"] = round(later[1] - up) if len(later) > 1 else None
    page.keyboard.press("Control+z")
    time.sleep(1)
    return row


def bench_live(args) -> list[dict]:
    """``live test --preview`` at 1280x720: each of --live-tools dragged over the live frames."""
    rows: list[dict] = []
    with served_page("live", args, live=True) as (_, page):
        for run in range(args.repeat):
            for tool in args.live_tools:
                row = {"run": run + 1, "load": os.getloadavg()[0]}
                row.update(live_gesture(page, tool, args))
                kept(rows, row)
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--design", nargs="+", default=["nonpareil", "bouquet", "64ops"])
    p.add_argument("--gestures", nargs="+", default=list(GESTURES), choices=GESTURES)
    p.add_argument("--repeat", type=int, default=1, help="runs of every gesture per design")
    p.add_argument("--seconds", type=float, default=2.0, help="length of a gesture (2)")
    p.add_argument("--rate", type=float, default=60.0, help="pointer moves per second (60)")
    p.add_argument("--viewport", default="1280x860", help="the window's CSS size (1280x860)")
    p.add_argument("--dpr", type=float, default=1.0, help="devicePixelRatio (1; 2: a HiDPI screen)")
    p.add_argument("--live", action="store_true", help="also live test --preview at 1280x720")
    p.add_argument("--live-tools", nargs="+", default=["comb", "stroke"], choices=GESTURES[:3])
    p.add_argument("--no-design", action="store_true", help="only --live")
    p.add_argument("--verify", action="store_true", help="also compare the settled sheet")
    p.add_argument("--pause", type=float, default=0.0, help="select -> press, s (handle, slider)")
    p.add_argument("--query", help="the page's address query, e.g. glsheet=0 (sheetgl.js)")
    p.add_argument("--json", metavar="FILE", help="write the rows as JSON")
    p.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"), help="two --json files")
    args = p.parse_args()
    if args.compare:
        before, after = (json.loads(Path(f).read_text())["rows"] for f in args.compare)
        return print(compare(before, after))
    args.viewport = tuple(int(v) for v in args.viewport.lower().split("x"))
    header()
    print(f"# load average: {' '.join(f'{v:.2f}' for v in os.getloadavg())}; viewport "
          f"{args.viewport[0]}x{args.viewport[1]} at DPR {args.dpr}; {args.rate:g} moves/s for "
          f"{args.seconds:g} s")  # fmt: skip
    rows = [] if args.no_design else [r for d in args.design for r in bench_design(d, args)]
    if args.live:
        rows += bench_live(args)
    print(table(rows))
    print(f"# load average at the end: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    if args.json:
        Path(args.json).write_text(json.dumps({"cpu": cpu_summary(), "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
