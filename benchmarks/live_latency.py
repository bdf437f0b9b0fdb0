"""Where a live preview's latency goes: one comb dragged over ``marblevideo live
test --size 1280x720 --preview`` (the designer benchmark's server, page and
pointer), the page's preview PUTs and JPEG fetches timed in the page.

Prints the live frames that answered inputs and their latency median (a pointer
move to the first live frame showing the preview made after it: X-Preview-Serial),
the PUTs' round trip and spacing, the JPEGs' spacing, and from a JPEG's arrival
to its drawing, and the session's figures (frames rendered, source frames
dropped, frames marbled again for a preview: ``redrawn``).

    python -m benchmarks.live_latency [--seconds 2] [--fps 30]

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from .designer_realtime import Pointer, path_of, served_page

WRAP = """() => { window.__timed = []; const f = window.fetch;
  window.fetch = (u, o) => { const s = performance.now(), p = f(u, o), url = String(u);
    const kind = url.includes('/api/preview') ? 'put' : url.includes('/frame.jpg') ? 'jpg' : null;
    if (kind) p.then(() => window.__timed.push({kind, s, e: performance.now()}));
    return p; }; }"""


def median(values) -> float:
    return round(statistics.median(values), 1) if values else float("nan")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seconds", type=float, default=2.0, help="length of the drag (2)")
    p.add_argument("--fps", type=float, default=None, help="the test source's rate (30)")
    args = argparse.Namespace(viewport=(1280, 860), dpr=1, **vars(p.parse_args()))
    with served_page("live", args, live=True, fps=args.fps) as (_, page):
        page.evaluate(WRAP)
        page.evaluate("designer.setTool('comb')")
        first = page.evaluate("window.marbleFrames.length")
        pointer = Pointer(page)
        pointer.drag(path_of(page, "comb", int(60 * args.seconds)), 60, hold=0.3)
        pointer.up()
        time.sleep(1.5)
        frames = page.evaluate("window.marbleFrames")[first:]
        timed = page.evaluate("window.__timed")
        stats = page.evaluate("fetch('/stats').then((r) => r.json())")
    answered = [f for f in frames if f["kind"] == "live" and f["input"] is not None]
    puts = [t for t in timed if t["kind"] == "put"]
    jpgs = [t for t in timed if t["kind"] == "jpg"]
    got = [max((j["e"] for j in jpgs if j["e"] <= f["drawnAt"]), default=None) for f in answered]
    gaps = lambda xs, k: [b[k] - a[k] for a, b in zip(xs, xs[1:], strict=False)]  # noqa: E731
    drawn = [f["drawnAt"] - g for f, g in zip(answered, got, strict=True) if g is not None]
    print(f"load average {os.getloadavg()[0]:.2f}")
    lat = median([f["drawnAt"] - f["inputAt"] for f in answered])
    print(f"live frames answering inputs: {len(answered)}, latency median {lat} ms")
    trip = median([t["e"] - t["s"] for t in puts])
    print(f"preview PUTs: {len(puts)}, round trip median {trip} ms, one every "
          f"{median(gaps(puts, 's'))} ms")  # fmt: skip
    print(f"JPEGs: one every {median(gaps(jpgs, 'e'))} ms; arrival to drawn median "
          f"{median(drawn)} ms")  # fmt: skip
    print(f"session: {stats['frames']} frames rendered, {stats['dropped']} source frames "
          f"dropped, {stats.get('redrawn', 'no')} redrawn for a preview; render median "
          f"{stats['render_ms']} ms, capture to JPEG median {stats['latency_ms']} ms")  # fmt: skip


if __name__ == "__main__":
    main()
