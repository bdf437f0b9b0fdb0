"""Benchmark of ``marblevideo design``: latency from a gesture to the updated frame
on the page, at 1024x768, in a real headless Chromium (Playwright).

Runs the real command (a subprocess serving the page on 127.0.0.1) on a blank
1024x768 sheet holding DESIGN (``light``: 6 ops; ``nonpareil``: the bundled
nonpareil scaled to the sheet, 140 drops and 3 rakes), and measures in the page
(performance.now()):

- click: a click with the drop tool (pointer up) -> the first frame drawn (the
  page's draft of the new recipe), and -> the exact (RGSS) 1024x768
  frame with the new drop drawn on the page's canvas (PUT, render, PNG, decode,
  draw);
- drag: a pointer move while dragging the comb tool -> the draft frame (no
  antialiasing, 512x384, drawn scaled) of the comb at that point;
- api: from Python, without the browser: PUT /api/recipe with the first op's
  point moved (the program stays) or with a drop added (a new program: PoCL
  builds it), then GET /api/frame.png (exact, 1024x768).

    python -m benchmarks.design_bench [--repeat 15] [--design light nonpareil]

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

from .common import ENV, ROOT, cpu_summary

SIZE = (1024, 768)
LIGHT = [
    {"type": "drop", "center": [512, 384], "radius": 160, "color": "#1d3557"},
    {"type": "drop", "center": [512, 384], "radius": 90, "color": "#e9c46a"},
    {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 64, "alpha": 40, "lambda": 14},
    {"type": "wave", "amplitude": 12, "wavelength": 200, "phase": 0, "angle": 0},
    {"type": "vortex", "center": [512, 384], "alpha": 300, "lambda": 120},
    {"type": "tine", "point": [0, 600], "angle": 0, "alpha": 80, "lambda": 30},
]

# installed in the page: the time from a pointer event to the next frame drawn of its kind
PROBE = """() => {
  const sheet = document.getElementById('sheet'), overlay = document.getElementById('overlay');
  window.marks = {click: [], first: [], drag: []};
  let up = null, move = null, first = null;
  overlay.addEventListener('pointerup', () => { up = first = [performance.now(), version]; },
    true);
  overlay.addEventListener('pointermove', (e) => { if (e.buttons) move = performance.now(); },
    true);
  new MutationObserver(() => {
    const now = performance.now(), d = sheet.dataset;
    if (first !== null) { marks.first.push(now - first[0]); first = null; }
    if (d.draft === '1' && move !== null) { marks.drag.push(now - move); move = null; }
    if (d.draft === '0' && up !== null && Number(d.version) > up[1]) {
      marks.click.push(now - up[0]); up = null;
    }
  }).observe(sheet, {attributes: true, attributeFilter: ['data-frames']});
}"""


def design_ops(name: str) -> list[dict]:
    if name == "light":
        return LIGHT
    doc = json.loads((ROOT / "samples" / "nonpareil.json").read_text())
    s = min(SIZE[0] / doc["canvas"][0], SIZE[1] / doc["canvas"][1])
    text = json.dumps(doc["ops"])
    ops = json.loads(text)
    for op in ops:  # scale the points and lengths to the sheet; no animation
        op.pop("start", None), op.pop("end", None)
        for key in ("center", "point", "size"):
            if key in op:
                op[key] = [v * s for v in op[key]]
        for key in ("radius", "alpha", "falloff", "spacing"):
            if key in op:
                op[key] *= s
    return ops


def quantiles(values: list[float]) -> str:
    values = sorted(values)
    p95 = values[min(len(values) - 1, int(0.95 * len(values)))]
    return f"{statistics.median(values):.0f} / {p95:.0f} ms (n={len(values)})"


def start(tmp: Path, ops: list[dict]):
    recipe = tmp / "bench.json"
    recipe.write_text(json.dumps({"canvas": list(SIZE), "background": "#f4f1de", "ops": ops}))
    proc = subprocess.Popen(
        [sys.executable, "-m", "marblevideo", "design", "--ops", str(recipe), "--no-browser",
         "--port", "0", "-q"],
        cwd=tmp, env=ENV, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    url = proc.stdout.readline().split(" ", 1)[1].strip()
    return proc, url, recipe


def api_change(url: str, recipe: Path, k: int, add: bool) -> tuple[float, float]:
    """A change through the API, then the exact frame: (ms, of which the PNG GET).
    ``add``: a drop added (a new structure: an OpenCL build), else the first
    op's point moved (the same program, new values)."""
    doc = json.loads(recipe.read_text())
    if add:
        doc["ops"].append({"type": "drop", "center": [100 + k, 100], "radius": 20, "color": "red"})
    else:
        key = "center" if "center" in doc["ops"][0] else "point"
        doc["ops"][0][key] = [v + 1 for v in doc["ops"][0][key]]
    t0 = time.perf_counter()
    req = urllib.request.Request(url + "api/recipe", data=json.dumps(doc).encode(), method="PUT")
    req.add_header("Content-Type", "application/json")
    urllib.request.urlopen(req).read()
    t1 = time.perf_counter()
    urllib.request.urlopen(url + "api/frame.png").read()
    t2 = time.perf_counter()
    return (t2 - t0) * 1000, (t2 - t1) * 1000


def bench(name: str, repeat: int) -> dict:
    from playwright.sync_api import TimeoutError, sync_playwright  # noqa: A004

    with tempfile.TemporaryDirectory() as folder:
        proc, url, recipe = start(Path(folder), design_ops(name))
        try:  # the API first: a browser closing would weigh on it
            edits = [api_change(url, recipe, k, False) for k in range(repeat + 2)][2:]
            adds = [api_change(url, recipe, k, True) for k in range(repeat + 2)][2:]
            with sync_playwright() as p:
                chromium = shutil.which("chromium") or "/usr/bin/chromium"
                browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
                page = browser.new_page(viewport={"width": 1450, "height": 950})
                page.goto(url)
                page.wait_for_selector("body[data-ready='1']")
                page.wait_for_function("document.getElementById('sheet').dataset.frames > 0")
                box = page.locator("#overlay").bounding_box()
                page.evaluate(PROBE)
                x0, y0 = box["x"], box["y"]
                for k in range(repeat + 2):  # the first two warm up (kernel builds)
                    page.mouse.click(x0 + 80 + 40 * k, y0 + 100)
                    page.wait_for_function(f"marks.click.length > {k}")
                    time.sleep(0.3)
                page.click("#tool-comb")
                page.mouse.move(x0 + 100, y0 + 500)
                page.mouse.down()
                for k in range(repeat + 2):
                    page.mouse.move(x0 + 120 + 30 * k, y0 + 520 + 5 * k)
                    with contextlib.suppress(TimeoutError):  # counted as missed
                        page.wait_for_function(f"marks.drag.length > {k}", timeout=5000)
                    time.sleep(0.1)  # under the 250 ms after which the exact draft is asked
                page.mouse.up()
                marks = page.evaluate("marks")
                browser.close()
        finally:
            proc.terminate()
            proc.wait(30)
    return {
        "design": name,
        "ops": len(design_ops(name)),
        "click -> first frame (draft)": quantiles(marks["first"][2:]),
        "click -> exact frame": quantiles(marks["click"][2:]),
        "drag -> draft frame": quantiles(marks["drag"][2:]),
        "drag moves without a draft": repeat + 2 - len(marks["drag"]),
        "api move a point: PUT + GET frame.png": quantiles([a for a, _ in edits]),
        "of which GET": quantiles([b for _, b in edits]),
        "api add a drop: PUT + GET frame.png": quantiles([a for a, _ in adds]),
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=15)
    p.add_argument("--design", nargs="+", default=["light", "nonpareil"])
    args = p.parse_args()
    print(f"# {platform.node()}, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M')}")
    print(f"# CPU: {cpu_summary()}")
    for name in args.design:
        print(json.dumps(bench(name, args.repeat)), flush=True)


if __name__ == "__main__":
    main()
