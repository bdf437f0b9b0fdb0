"""What designer_realtime.py installs in the page and computes from what it reads
there: the probe (JavaScript), the 64-op design, the figures (frames per second,
latency per input, agreement with the server's exact render) and the tables.

The probe records, in page time (performance.now()):

- the inputs: each pointer move with a button held while a gesture is timed
  (``benchProbe.mode`` "pointer"), or each ``input`` event of a slider (mode
  "slider"), at the event's ``timeStamp`` (when the browser took it in);
- the frames drawn on the sheet, from the page's own record where it has one
  (``window.marbleFrames``: each frame says which input it answers and when
  that input came), else from the sheet's ``data-frames`` counter, each frame
  answering the newest input at the start of the render (``fetch`` of
  ``/api/frame.rgba``) that drew it; live frames (``/frame.jpg``) answer none;
- a snapshot of the sheet's pixels (2D getImageData, or WebGL readPixels) at the
  first frame answering the input armed (the gesture's last, sent with twist 7), with what it
  shows (``window.marbleShown``, else the page's preview recipe and time).

A frame answers input i when the input it answers came no earlier than i.
"""

from __future__ import annotations

import base64
import json
import random
import statistics
import urllib.error
import urllib.parse
import urllib.request

import numpy as np

PROBE = r"""(() => {
  const B = window.benchProbe = {mode: null, inputs: [], frames: [], pageFrames: [], queue: [],
    puts: [], armSeq: null, armNext: false, snap: null};
  const latest = () => B.inputs.at(-1) || null;
  // the gesture's last move comes with twist 7 (no page reads it): the input it makes is armed
  addEventListener('pointermove', (e) => {
    const last = e.twist === 7 && B.armSeq === null;
    if (B.mode === 'pointer' && e.buttons) {
      if (last) B.armSeq = B.inputs.length;
      B.inputs.push({seq: B.inputs.length, at: e.timeStamp});
    } else if (last) B.armNext = true;
  }, true);
  addEventListener('input', (e) => {
    if (B.mode !== 'slider' || e.target.type !== 'range') return;
    if (B.armNext && B.armSeq === null) B.armSeq = B.inputs.length;
    B.inputs.push({seq: B.inputs.length, at: e.timeStamp});
  }, true);
  function readSheet() {
    const c = document.getElementById('sheet');
    if (window.designer && designer.sheetPixels) {  // whichever canvas shows the sheet
      const d = designer.sheetPixels();
      return {w: d.width, h: d.height, data: d.data};
    }
    const c2 = c.getContext('2d');
    if (c2) return {w: c.width, h: c.height, data: c2.getImageData(0, 0, c.width, c.height).data};
    const gl = c.getContext('webgl2') || c.getContext('webgl');
    if (!gl) return null;
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight, px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    const out = new Uint8ClampedArray(w * h * 4);
    for (let y = 0; y < h; y++) {
      out.set(px.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    }
    return {w, h, data: out, flipped: true};
  }
  function shown() {
    if (window.marbleShown) return JSON.parse(JSON.stringify(window.marbleShown));
    const s = window.designer.state, c = document.getElementById('sheet');
    return {doc: s.preview ? s.preview.doc : s.doc, t: s.t, w: c.width, h: c.height, view: null};
  }
  function maybeSnap(f) {
    if (B.armSeq === null || B.snap || B.inputs.length <= B.armSeq || f.inputAt === null) return;
    if (f.inputAt < B.inputs[B.armSeq].at - 0.5) return;
    B.snap = {frame: f, pixels: readSheet(), shown: shown(), at: performance.now()};
  }
  let pageList = null;
  function hook(list) {
    if (!Array.isArray(list) || list.benchHooked) return list;
    const push = list.push.bind(list);
    list.push = (...items) => {
      const n = push(...items);
      for (const it of items) {
        const f = {drawnAt: it.drawnAt, inputAt: it.input === null ? null : it.inputAt,
          kind: it.kind, w: it.w, h: it.h};
        // (a frame on the WebGL canvas gets its drawnAt once its draw is done: B.fresh)
        Object.defineProperty(f, 'src', {value: it, enumerable: false});
        B.pageFrames.push(f);
        maybeSnap(f);
      }
      return n;
    };
    list.benchHooked = true;
    return list;
  }
  Object.defineProperty(window, 'marbleFrames', {configurable: true,
    get: () => pageList, set: (v) => { pageList = hook(v); }});
  const realFetch = window.fetch.bind(window);
  window.fetch = (url, opts) => {
    const u = String(url), start = performance.now(), l = latest();
    const entry = u.includes('/api/frame.rgba') ? {inputAt: l ? l.at : null, kind: 'frame', start}
      : u.includes('/frame.jpg') ? {inputAt: null, kind: 'live', start} : null;
    if (entry) B.queue.push(entry);
    const put = opts && opts.method === 'PUT' && u.includes('/api/recipe');
    const p = realFetch(url, opts);
    p.then((r) => {
      if (put) B.puts.push({start, end: performance.now()});
      if (entry && !r.ok) B.queue.splice(B.queue.indexOf(entry), 1);
    }, () => { if (entry) B.queue.splice(B.queue.indexOf(entry), 1); });
    return p;
  };
  function observe() {
    const sheet = document.getElementById('sheet');
    if (!sheet) { requestAnimationFrame(observe); return; }
    new MutationObserver(() => {
      const d = sheet.dataset, e = B.queue.shift() || {inputAt: null, kind: 'frame', start: null};
      const kind = e.kind === 'live' ? 'live' : d.draft === '1' ? 'server-draft' : 'exact';
      const f = {drawnAt: performance.now(), inputAt: e.inputAt, kind, fetchedAt: e.start};
      B.frames.push(f);
      if (!Array.isArray(window.marbleFrames)) maybeSnap(f);
    }).observe(sheet, {attributes: true, attributeFilter: ['data-frames']});
  }
  if (document.readyState === 'loading') addEventListener('DOMContentLoaded', observe);
  else observe();
  // what the benchmark reads: the snapshot's pixels as base64
  // (``now``: the sheet as it is, e.g. settled on the exact frame, and what it shows)
  B.fresh = () => { for (const f of B.pageFrames) if (f.src) f.drawnAt = f.src.drawnAt; };
  B.snapPixels = (now = false) => {
    if (now) B.snap = {frame: {kind: 'now'}, pixels: readSheet(), shown: shown()};
    const p = B.snap && B.snap.pixels;
    if (!p) return null;
    let s = '';
    for (let i = 0; i < p.data.length; i += 0x8000) {
      s += String.fromCharCode.apply(null, p.data.subarray(i, i + 0x8000));
    }
    return {w: p.w, h: p.h, b64: btoa(s)};
  };
})();"""


def design64(seed: int = 39) -> dict:
    """A 1024x768 design of 64 ops, the same every time: 24 drops, 10 combs, 8
    waves, 10 vortices and 12 strokes, interleaved."""
    rnd = random.Random(seed)
    inks = ["#1d3557", "#e9c46a", "#b23a48", "#2a9d8f", "#e76f51", "#457b9d", "#f4a261"]
    kinds = ["drop"] * 24 + ["comb"] * 10 + ["wave"] * 8 + ["vortex"] * 10 + ["stroke"] * 12
    rnd.shuffle(kinds)
    kinds.remove("drop"), kinds.insert(0, "drop")  # ink first
    pt = lambda: [round(rnd.uniform(80, 944), 1), round(rnd.uniform(60, 708), 1)]  # noqa: E731
    ops = []
    for kind in kinds:
        if kind == "drop":
            op = {
                "center": pt(),
                "radius": round(rnd.uniform(30, 140), 1),
                "color": rnd.choice(inks),
            }
        elif kind == "comb":
            op = {"point": pt(), "angle": rnd.choice([0, 45, 90, 135, 180, 270]),
                  "spacing": rnd.choice([48, 64, 96]), "alpha": rnd.choice([-40, 30, 50]),
                  "lambda": rnd.choice([12, 16, 24])}  # fmt: skip
        elif kind == "wave":
            op = {"amplitude": rnd.uniform(8, 30), "wavelength": rnd.uniform(120, 320),
                  "phase": rnd.uniform(0, 360), "angle": rnd.choice([0, 30, 90, 120])}  # fmt: skip
        elif kind == "vortex":
            op = {"center": pt(), "alpha": rnd.choice([-300, 200, 400]),
                  "lambda": rnd.uniform(60, 160)}  # fmt: skip
        else:
            a, n = pt(), 12
            points = [
                [round(a[0] + 25 * k, 1), round(a[1] + 40 * np.sin(k / 2), 1)] for k in range(n)
            ]
            op = {"points": points, "width": rnd.choice([16, 24, 40])}
        ops.append({"type": kind, **op})
    return {"marblevideo": 1, "canvas": [1024, 768], "background": "#f4f1de", "antialias": "rgss",
            "ops": ops}  # fmt: skip


def quantile(values: list[float], q: float) -> float:
    values = sorted(values)
    return values[min(len(values) - 1, int(q * len(values)))]


def figures(probe: dict) -> dict:
    """fps and latency of one timed gesture from the probe's record: frames drawn
    per second between its first and last input; per input, the first frame
    answering it (drawn after it, answering an input no earlier)."""
    inputs = probe["inputs"]
    frames = probe["pageFrames"] if probe["source"] == "page" else probe["frames"]
    if not inputs:
        return {"inputs": 0, "fps": 0.0, "frames": 0}
    t0, t1 = inputs[0]["at"], inputs[-1]["at"]
    during = [f for f in frames if t0 <= f["drawnAt"] <= t1]
    answered = sorted((f for f in frames if f["inputAt"] is not None), key=lambda f: f["drawnAt"])
    lat, never = [], 0
    for i in inputs:
        first = next(
            (f for f in answered if f["inputAt"] >= i["at"] - 0.5 and f["drawnAt"] >= i["at"]), None
        )
        if first is None:
            never += 1
        else:
            lat.append(first["drawnAt"] - i["at"])
    exact = {f["inputAt"] for f in answered}
    shown = sum(1 for i in inputs if any(abs(a - i["at"]) <= 0.5 for a in exact))
    kinds = sorted({f["kind"] for f in during})
    return {
        "inputs": len(inputs),
        "seconds": round((t1 - t0) / 1000, 2),
        "frames": len(during),
        "fps": round(len(during) / max(1e-3, (t1 - t0) / 1000), 1),
        "latency_median_ms": round(statistics.median(lat), 1) if lat else None,
        "latency_p95_ms": round(quantile(lat, 0.95), 1) if lat else None,
        "never_answered": never,
        "shown_exactly": shown,
        "kinds": kinds,
    }


def agreement(sheet: np.ndarray, exact: np.ndarray, tol: int = 8) -> float:
    """The share of pixels whose RGB channels all differ by at most ``tol``."""
    diff = np.abs(sheet[..., :3].astype(np.int16) - exact[..., :3].astype(np.int16)).max(axis=2)
    return float((diff <= tol).mean())


COLUMNS = [
    ("design", "design"), ("gesture", "gesture"), ("run", "run"), ("load", "load 1m"),
    ("fps", "fps"), ("latency_median_ms", "lat. median ms"), ("latency_p95_ms", "lat. p95 ms"),
    ("never_answered", "never / inputs"), ("agree", "agree (8 lv)"), ("kinds", "frame kinds"),
    ("up_to_exact_ms", "up->exact ms"),
]  # fmt: skip


def table(rows: list[dict]) -> str:
    """The rows as a Markdown table."""

    def cell(row, key):
        v = row.get(key)
        if key == "never_answered":
            return f"{v} / {row.get('inputs')}"
        if key == "agree" and v is not None:
            return f"{100 * v:.1f}% ({row.get('agree_frame')}, {row.get('agree_size')})"
        if key == "up_to_exact_ms" and "up_to_live_ms" in row:
            return f"{row['up_to_live_ms']} (to live)"
        if key == "load":
            return f"{v:.2f}"
        return ",".join(v) if isinstance(v, list) else "-" if v is None else str(v)

    lines = ["| " + " | ".join(t for _, t in COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(cell(r, k) for k, _ in COLUMNS) + " |" for r in rows]
    return "\n".join(lines)


def _runs(rows: list[dict]) -> dict:
    """(design, gesture) -> its runs, in order."""
    out: dict = {}
    for r in rows:
        out.setdefault((r["design"], r["gesture"]), []).append(r)
    return out


def _span(runs: list[dict], key: str, fmt: str = "{:.0f}") -> str:
    """The median of the runs' values (their range beside it when they differ)."""
    vals = [r[key] for r in runs if r.get(key) is not None]
    if not vals:
        return "-"
    mid = fmt.format(statistics.median(vals))
    lo, hi = fmt.format(min(vals)), fmt.format(max(vals))
    return mid if lo == hi else f"{mid} ({lo}-{hi})"


def _agree(runs: list[dict]) -> str:
    """The runs' agreement of mid-gesture frames (a run whose frame answering the
    last move was the exact render is left out, marked *)."""
    mid = [r for r in runs if r.get("agree_frame") != "exact"]
    return _span(mid, "agree", "{:.1%}") + ("*" if len(mid) < len(runs) else "")


def _never(runs: list[dict]) -> str:
    return f"{sum(r.get('never_answered') or 0 for r in runs)}/{sum(r['inputs'] for r in runs)}"


def compare(before: list[dict], after: list[dict]) -> str:
    """Before and after side by side, per design and gesture: medians over the runs
    (their range in brackets), inputs never answered over all runs."""
    b, a = _runs(before), _runs(after)
    head = "| design | gesture | fps before | after | latency median / p95 ms before | after |"
    head += " never answered before | after | agree before | after |"
    lines = [head, "|" + "---|" * 10]
    for key in list(b) + [k for k in a if k not in b]:
        rb, ra = b.get(key, []), a.get(key, [])
        cells = [*key, _span(rb, "fps", "{:.1f}"), _span(ra, "fps", "{:.1f}")]
        for runs in (rb, ra):
            cells.append(f"{_span(runs, 'latency_median_ms')} / {_span(runs, 'latency_p95_ms')}")
        cells += [_never(rb), _never(ra), _agree(rb), _agree(ra)]
        lines.append("| " + " | ".join(c if c != "0/0" else "-" for c in cells) + " |")
    return "\n".join(lines)


def exact_frame(url: str, shown: dict) -> np.ndarray:
    """The server's exact render of what a frame shows (``marblevideo.design``'s frame.rgba)."""
    q = {"t": f"{shown['t']:.3f}", "w": str(shown["w"]), "h": str(shown["h"])}
    if shown.get("view"):  # the window of the canvas shown: x,y,w,h in canvas units
        q["view"] = ",".join(str(round(v, 6)) for v in shown["view"])
    if shown.get("ops") is not None:  # a solo
        q["ops"] = ",".join(str(i) for i in shown["ops"])
    req = urllib.request.Request(
        url + "api/frame.rgba?" + urllib.parse.urlencode(q), data=json.dumps(shown["doc"]).encode(),
        headers={"Content-Type": "application/json"}, method="POST",
    )  # fmt: skip
    raw = urllib.request.urlopen(req, timeout=300).read()
    w, h = np.frombuffer(raw[:8], "<u4")
    return np.frombuffer(raw[8:], np.uint8).reshape(int(h), int(w), 4)


def agree(url: str, snap: dict | None, pixels: dict | None) -> dict:
    """The snapshot's agreement with the exact render of what it shows."""
    if not snap or not pixels:
        return {"agree": None, "agree_note": "no frame answered the last input"}
    sheet = np.frombuffer(base64.b64decode(pixels["b64"]), np.uint8)
    sheet = sheet.reshape(pixels["h"], pixels["w"], 4)
    try:
        exact, note = exact_frame(url, snap["shown"]), ""
    except urllib.error.HTTPError as exc:  # the server refused what the page says it shows
        return {"agree": None, "agree_note": f"exact render refused: {exc.read()[:300]!r}"}
    if exact.shape[:2] != sheet.shape[:2]:
        import cv2

        note = f"exact {exact.shape[1]}x{exact.shape[0]} resized to the sheet's"
        exact = cv2.resize(exact, (sheet.shape[1], sheet.shape[0]), interpolation=cv2.INTER_AREA)
    kind = snap["frame"]["kind"]
    return {"agree": round(agreement(sheet, exact), 4), "agree_frame": kind,
            "agree_size": f"{sheet.shape[1]}x{sheet.shape[0]}", "agree_note": note}  # fmt: skip
