"""Benchmark of the page's WebGL2 warp (marblevideo/design/web/warp.js): the time
of one ``warp.draw`` per frame, in a real headless Chromium (Playwright), whose
WebGL2 runs on SwiftShader (the CPU) on a machine without a GPU.

At each size (1024x768 and 1600x1000 device pixels, a textured base), in the
page (performance.now(), each frame ended by a 1-pixel readPixels so the GPU
work is inside the time):

- drop: a drop growing (start 0, end 1) at a new t each frame;
- comb: a comb pulled (alpha growing) at a new t each frame;
- rake: a rake of 43 tines (nonpareil's last op, scaled) pulled likewise;
- stroke: a 200-point stroke with ``times`` drawn point by point (60 points a
  second, width 24, two tines), each frame the gesture so far at its newest
  point's time: whole steps folded into the map by chunks, the rest walked.

Reports the median, 90th percentile and worst frame of each, with the load average.

    python -m benchmarks.warp_bench [--frames 60] [--sizes 1024x768 1600x1000]

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import os
import shutil

from .webfolder import ARGS, serve_web

BENCH = """async ([w, h, frames]) => {
  const warp = await import("/web/warp.js");
  const canvas = document.createElement("canvas");
  canvas.width = w; canvas.height = h;
  const W = warp.createWarp(canvas);
  if (!W) return null;
  const px = new Uint8ClampedArray(w * h * 4);
  for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) {
    const i = 4 * (y * w + x);
    px[i] = 128 + 100 * Math.sin(x / 17); px[i + 1] = 128 + 100 * Math.sin(y / 23);
    px[i + 2] = (x ^ y) & 255; px[i + 3] = 255;
  }
  W.setBase(new ImageData(px, w, h), w, h);
  W.setGeometry([1, 1, 0, 0], [1, 1, 0, 0]);
  const gl = canvas.getContext("webgl2"), one = new Uint8Array(4);
  const time = (draw) => {
    const t0 = performance.now();
    draw();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    return performance.now() - t0;
  };
  const cx = w / 2, cy = h / 2, out = {};
  const win = { start: 0, end: 1 };
  const drop = { type: "drop", center: [cx, cy], radius: h / 5, color: "#c03020", ...win };
  const comb = { type: "comb", point: [cx, cy], angle: 30, spacing: h / 16, alpha: h / 20,
    lambda: h / 60, ...win };
  // nonpareil's top op: a rake of 43 tines (closed form in the shader since issue 39)
  const rake = { type: "rake", point: [cx, cy], angle: 0, alpha: h / 32, falloff: h / 128,
    spacing: h / 40, count: 43, ...win };
  for (const [name, op] of [["drop", drop], ["comb", comb], ["rake", rake]]) {
    time(() => W.draw(op, 0.5));
    const at = (k) => (k + 1) / (frames + 1);
    out[name] = Array.from({ length: frames }, (_, k) => time(() => W.draw(op, at(k))));
  }
  const pts = [], times = [];
  for (let i = 0; i < 200; i++) {
    const a = (4 * Math.PI * i) / 199, r = 0.3 * h * (0.4 + (0.6 * i) / 199);
    pts.push([cx + r * Math.cos(a), cy + 0.8 * r * Math.sin(a)]);
    times.push(i / 60);
  }
  out.stroke = [];
  for (let i = 1; i < 200; i++) {
    const op = { type: "stroke", points: pts.slice(0, i + 1), times: times.slice(0, i + 1),
      width: 24, drag: 1, tines: [0, 20] };
    out.stroke.push(time(() => W.draw(op, times[i])));
  }
  return out;
}"""


def stats(ms: list[float]) -> str:
    s = sorted(ms)
    return f"{s[len(s) // 2]:.1f} / {s[int(0.9 * (len(s) - 1))]:.1f} / {s[-1]:.1f}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--sizes", nargs="+", default=["1024x768", "1600x1000"])
    args = ap.parse_args(argv)
    from playwright.sync_api import sync_playwright

    chromium = os.environ.get("MARBLEVIDEO_CHROMIUM") or shutil.which("chromium")
    print("| size | op | ms per frame: median / p90 / worst | load average |")
    print("|---|---|---|---|")
    with serve_web() as url, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=ARGS)
        page = browser.new_page()
        page.goto(url + "/")
        for size in args.sizes:
            w, h = (int(v) for v in size.split("x"))
            out = page.evaluate(BENCH, [w, h, args.frames])
            if out is None:
                print(f"| {size} | - | no WebGL2 with float targets | |")
                continue
            load = " ".join(f"{v:.2f}" for v in os.getloadavg())
            for name in ("drop", "comb", "rake", "stroke"):
                print(f"| {size} | {name} | {stats(out[name])} | {load} |", flush=True)
        browser.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
