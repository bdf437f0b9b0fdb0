"""Where a live preview's latency goes: one comb dragged over ``marblevideo live
test --size 1280x720 --preview`` (the designer benchmark's server, page and
pointer), the page's preview PUTs and JPEG fetches timed in the page.

Prints the live frames that answered inputs and their latency median and p95 (a
pointer move to the first live frame showing it: the page's warp of the newest
live frame, ``live-warp``, or the session's frame of the preview made after it,
X-Preview-Serial; each alone too),
the PUTs' round trip and spacing, the JPEGs' spacing, and from a JPEG's arrival
to its drawing, and the session's figures (frames rendered, source frames
dropped, frames marbled again for a preview: ``redrawn``), and the answered
frames' timeline: pointer move, PUT sent, the session's times for the preview
(``/stats`` ``preview_times``: taken, render started and done, JPEG ready),
JPEG fetched, drawn (wall-clock ms on the one machine).

    python -m benchmarks.live_latency [--seconds 2] [--fps 30] [--no-page]

``--no-page``: no browser; 40 previews (a drop moved) PUT over HTTP one after
another, each timed from its PUT to the first JPEG tagged with its serial (the
session's part alone, on a machine where Chromium takes no cores).

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import tempfile
import time
import urllib.request
from pathlib import Path

from .designer_realtime import LIVE_RECIPE, Pointer, path_of, serve, served_page

WRAP = """() => { window.__timed = []; const f = window.fetch, T = performance.timeOrigin;
  window.fetch = (u, o) => { const s = performance.now(), p = f(u, o), url = String(u);
    const kind = url.includes('/api/preview') ? 'put' : url.includes('/frame.jpg') ? 'jpg' : null;
    if (kind === 'jpg') p.then((r) => window.__timed.push({kind, s, e: performance.now(), T,
      serial: Number(r.headers.get('X-Preview-Serial') || 0)}));
    if (kind === 'put') p.then((r) => { const e = performance.now();
      r.clone().json().then((j) => window.__timed.push({kind, s, e, T, serial: j.serial || 0})); });
    return p; }; }"""

#: the steps of one live frame's way from the pointer move it answers to its drawing
STEPS = ("input", "put", "received", "start", "rendered", "ready", "fetched", "drawn")


def median(values) -> float:
    return round(statistics.median(values), 1) if values else float("nan")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seconds", type=float, default=2.0, help="length of the drag (2)")
    p.add_argument("--fps", type=float, default=None, help="the test source's rate (30)")
    p.add_argument("--no-page", action="store_true", help="previews PUT over HTTP, no browser")
    args = argparse.Namespace(viewport=(1280, 860), dpr=1, **vars(p.parse_args()))
    if args.no_page:
        return without_page(args.fps)
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
    # a live frame answers an input once: the page's warp of the newest live frame
    # ("live-warp", mid-gesture), or the session's own frame of its preview ("live")
    answered = [f for f in frames if f["kind"] == "live" and f["input"] is not None]
    warped = [f for f in frames if f["kind"] == "live-warp" and f["input"] is not None]
    puts = [t for t in timed if t["kind"] == "put"]
    jpgs = [t for t in timed if t["kind"] == "jpg"]
    got = [max((j["e"] for j in jpgs if j["e"] <= f["drawnAt"]), default=None) for f in answered]
    steps = timeline(answered, puts, jpgs, stats.get("preview_times", {}))
    gaps = lambda xs, k: [b[k] - a[k] for a, b in zip(xs, xs[1:], strict=False)]  # noqa: E731
    drawn = [f["drawnAt"] - g for f, g in zip(answered, got, strict=True) if g is not None]
    print(f"load average {os.getloadavg()[0]:.2f}")
    late = lambda fs: [f["drawnAt"] - f["inputAt"] for f in fs]  # noqa: E731
    both = sorted(late(answered + warped))
    p95 = round(both[int(0.95 * (len(both) - 1))], 1) if both else float("nan")
    print(f"live frames answering inputs: {len(both)}, latency median {median(both)} ms, "
          f"p95 {p95} ms")  # fmt: skip
    print(f"  warped on the page: {len(warped)}, median {median(late(warped))} ms; "
          f"the session's: {len(answered)}, median {median(late(answered))} ms")  # fmt: skip
    trip = median([t["e"] - t["s"] for t in puts])
    print(f"preview PUTs: {len(puts)}, round trip median {trip} ms, one every "
          f"{median(gaps(puts, 's'))} ms")  # fmt: skip
    print(f"JPEGs: one every {median(gaps(jpgs, 'e'))} ms; arrival to drawn median "
          f"{median(drawn)} ms")  # fmt: skip
    print(f"session: {stats['frames']} frames rendered, {stats['dropped']} source frames "
          f"dropped, {stats.get('redrawn', 'no')} redrawn for a preview; render median "
          f"{stats['render_ms']} ms, capture to JPEG median {stats['latency_ms']} ms")  # fmt: skip
    if steps:
        print(f"timeline of {len(steps)} answered frames, median ms per step (mean in brackets):")
        for a, b in zip(STEPS, STEPS[1:], strict=False):
            part = [t[b] - t[a] for t in steps]
            print(f"  {a:>8} -> {b:<8} {median(part):7.1f} ({statistics.fmean(part):.1f})")


def timeline(answered, puts, jpgs, times) -> list[dict]:
    """Each answered frame's steps (:data:`STEPS`, wall-clock ms): the page's
    input, its preview's PUT sent, the session's times for that preview
    (``/stats`` ``preview_times``), its JPEG's fetch resolved, drawn."""
    rows = []
    for f in answered:
        jpg = max((j for j in jpgs if j["e"] <= f["drawnAt"]), key=lambda j: j["e"], default=None)
        put = next((p for p in puts if jpg and p["serial"] == jpg["serial"]), None)
        server = times.get(str(jpg["serial"])) if jpg else None
        if put is None or not server or len(server) < 4:
            continue
        row = {"input": f["inputAt"] + put["T"], "put": put["s"] + put["T"]}
        row |= {k: server[k] for k in ("received", "start", "rendered", "ready")}
        rows.append(row | {"fetched": jpg["e"] + jpg["T"], "drawn": f["drawnAt"] + put["T"]})
    return rows


def without_page(fps: float | None, count: int = 40) -> None:
    """``count`` previews PUT one after another, each timed to the first JPEG that shows it."""
    with tempfile.TemporaryDirectory() as folder:
        proc, url = serve(Path(folder), "live", live=True, fps=fps)

        def ask(method: str, path: str, body=None):
            data = None if body is None else json.dumps(body).encode()
            request = urllib.request.Request(url.rstrip("/") + path, data, method=method)
            request.add_header("Content-Type", "application/json")
            with urllib.request.urlopen(request, timeout=10) as answer:
                return answer.read(), answer.headers

        try:
            time.sleep(2.0)  # built, frames coming
            version, took = json.loads(ask("GET", "/api/info")[0])["version"], []
            for k in range(count):
                drop = {"type": "drop", "center": [200 + 10 * k, 300], "radius": 80}
                doc = {**LIVE_RECIPE, "ops": [*LIVE_RECIPE["ops"], {**drop, "color": "#e63946"}]}
                start = time.perf_counter()
                put = ask("PUT", "/api/preview", {"recipe": doc, "version": version})[0]
                serial, seq = (
                    json.loads(put)["serial"],
                    json.loads(ask("GET", "/stats")[0])["jpeg_seq"],
                )
                while True:
                    _, head = ask("GET", f"/frame.jpg?after={seq}")
                    seq = int(head["X-Frame-Seq"])
                    if int(head.get("X-Preview-Serial") or 0) >= serial:
                        break
                took.append((time.perf_counter() - start) * 1000)
                time.sleep(0.02)
            stats = json.loads(ask("GET", "/stats")[0])
        finally:
            proc.terminate()
            proc.wait(30)
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(f"previews: {count}, PUT to the JPEG showing it: median {median(took)} ms, "
          f"p90 {round(sorted(took)[int(0.9 * count)], 1)} ms")  # fmt: skip
    print(f"session: {stats['frames']} frames rendered, {stats.get('redrawn', 'no')} redrawn "
          f"for a preview; render median {stats['render_ms']} ms")  # fmt: skip


if __name__ == "__main__":
    main()
