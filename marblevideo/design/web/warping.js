// The sheet during a gesture that changes one op k (a new op on top, a handle
// dragged, a slider): the page warps an exact picture of the ops below k by op k
// alone (warp.js, WebGL2), and paints what the ops above k do from their map.
// The picture and the map are the server's layers of k (POST /api/layers),
// asked once per gesture; for a new op on top the page's own exact frame of the
// recipe is the picture, when it shows the same recipe, time, view and size.
// Where the page cannot (no WebGL2, an op warp.js does not draw, layers not
// here yet) the caller asks the server for a frame instead.
import * as api from "./api.js";
import { toCanvasMap, viewOf } from "./view.js";
import * as lib from "./warp.js";

// (``?warp=0`` in the page's address: the server's frames only, for tests and benchmarks)
let warp = null, canvas = null, broken = new URLSearchParams(location.search).get("warp") === "0";
let ready = null, loading = null, wanted = null, failed = null, again = () => {};
// ``fn`` runs when layers come (the sheet draws the gesture again).
export function whenLayers(fn) { again = fn; }

function available(w, h) {
  if (broken) return false;
  if (!warp) {
    broken = !lib.supported();
    if (broken) return false;
    canvas = document.createElement("canvas");
    canvas.width = w; canvas.height = h;
    warp = lib.createWarp(canvas);
    broken = !warp;
    if (broken) return false;
  }
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = w; canvas.height = h;
    ready = null;
  }
  return true;
}

// The op that ``next`` changes of ``doc``: its index (the length of doc's ops:
// a new op on top), "same" (nothing changed), or null (more than one op, or
// anything else, changed).
export function changedOp(doc, next) {
  const a = doc.ops, b = next.ops;
  if (b.length !== a.length && b.length !== a.length + 1) return null;
  if (rest(doc) !== rest(next)) return null;
  let k = b.length > a.length ? a.length : null;
  for (let i = 0; i < a.length; i++) {
    if (a[i] === b[i] || JSON.stringify(a[i]) === JSON.stringify(b[i])) continue;
    if (k !== null) return null;
    k = i;
  }
  return k === null ? "same" : k;
}
const rest = (doc) => JSON.stringify({...doc, ops: null});
const viewText = (view) => view.map((v) => +v.toFixed(6)).join(",");
// From which time on the picture below op k and the ops above it stay the same
// (Infinity: never; -Infinity: always): the last of their keys, `start`, `end`
// and `times` and the background's keys; a `heal` or a signal moves them at any
// time. A stroke drawn in time moves the time shown: past this, it keeps its layers.
const track = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
function lastTime(v) {
  if (!track(v)) return Array.isArray(v) ? Math.max(-Infinity, ...v.map(lastTime)) : -Infinity;
  return Array.isArray(v.keys) ? Math.max(...v.keys.map((key) => key.t)) : Infinity;  // a signal: always
}
function settles(op) {
  if ("heal" in op) return Infinity;
  const own = [op.start, op.end, ...(op.times || [])].filter((x) => typeof x === "number");
  return Math.max(-Infinity, ...own, ...Object.entries(op).filter(([f]) => f !== "times").map(([, v]) => lastTime(v)));
}
export const settledFrom = (doc, k) => Math.max(lastTime(doc.background), ...doc.ops.map((op, i) => (i === k ? -Infinity : settles(op))));
// ``settled``: whether the time shown is past settledFrom (the layers are then any such time's)
function keyOf(doc, k, t, settled, view, w, h) {
  const ops = doc.ops.filter((_, i) => i !== k), when = settled ? "settled" : t.toFixed(3);
  return `${k}|${when}|${viewText(view)}|${w}x${h}|${JSON.stringify({...doc, ops})}`;
}

// How the warp samples outside the picture: a blank sheet clamps, an input
// takes the recipe's ``edges``.
const edgesOf = (s, doc) => (s.info.input.kind === "blank" ? "clamp" : doc.edges || "clamp");

// Draw the preview of ``s`` (op k changed) by warping, through ``draw(job)``
// (job() draws into a canvas of the sheet's size at the next animation frame and
// returns {read, canvas, shown}, or null: it could not; read(all) gives the pixels,
// {image, rect}: all, or only those changed since the warp's frame before; ``answer``: the inputs it
// answers, given back with it); false when the page
// cannot warp it now (the caller asks the server). ``exact``: the page's last
// exact frame of the saved recipe, or null; ``shown()``: the sheet's picture
// when its last frame was warped, or null (a base until the exact one comes).
export function warpFrame(s, k, answer, draw, exact, shown) {
  const [w, h] = s.screen, view = viewOf(s), doc = s.preview.doc, t = s.t;
  if (!available(w, h)) return false;
  const since = settledFrom(doc, k), settled = t >= since;
  const key = keyOf(doc, k, t, settled, view, w, h);
  if (ready !== key) {
    const top = k === s.doc.ops.length;
    const from = settled ? since : null;
    const base = top ? baseOf(s, exact, view, w, h, from) || baseOf(s, shown(), view, w, h, from) : null;
    if (base) setLayers(key, base, null, view, w, h);
    else {
      // while its layers are on their way the frame waits for them (whenLayers
      // draws the newest input then): a server frame meanwhile would only slow
      // them down on the same cores; it is asked for when they cannot come
      ask(doc, k, t, view, w, h, key);
      if (failed === key || (loading !== key && (wanted === null || wanted.key !== key))) return false;
      if (!meanwhile(s, k, exact, view, w, h, key)) return true;
    }
  }
  const op = doc.ops[k], edges = edgesOf(s, doc);
  const old = s.doc.ops[k];
  draw(() => {
    // (the layers may have come since: then they are the base, as they are asked)
    const before = ready === key ? null : old;
    if (before !== null && ready !== interimKey(key, before)) return null;
    const ok = warp.draw(op, t, doc.background === undefined ? "#ffffff" : doc.background, edges, before);
    return ok ? {read: (all) => warp.read(all), canvas, shown: {doc, t: +t.toFixed(3), w, h, view, ops: null}} : null;
  }, answer);
  return true;
}
// While the layers of a handle or slider on the top op are on their way: the
// page's exact frame of the saved recipe is a base too, with the op as it was
// on top, which the warp takes off forward (warp.js ``before``: exact where the
// op's forward is closed-form and its pull stays inside the view). True when
// that base is set (uploaded once a gesture).
const interimKey = (key, before) => `before|${key}|${JSON.stringify(before)}`;
function meanwhile(s, k, exact, view, w, h, key) {
  const doc = s.doc, before = doc.ops[k];
  if (k !== doc.ops.length - 1 || s.preview.doc.ops.length !== doc.ops.length) return false;
  if (before.hidden || doc.motion !== undefined || !lib.forwardable(s.preview.doc.ops[k], before, s.t)) return false;
  const ikey = interimKey(key, before);
  if (ready === ikey) return true;
  const base = baseOf(s, exact, view, w, h, null);
  if (base) setLayers(ikey, base, null, view, w, h);
  return !!base;
}
// The pixels of ``f`` ({doc, t, view, image}: the page's exact frame, the
// sheet's last warped one) when it shows the recipe of ``s`` at its time, view
// and size (at any time from ``settled`` on, when not null: the recipe no longer
// moves there); else null.
function baseOf(s, f, view, w, h, settled) {
  const same = f && (f.doc === s.doc || JSON.stringify(f.doc) === JSON.stringify(s.doc));
  const when = settled !== null ? f && f.t >= settled : f && f.t === +s.t.toFixed(3);
  return same && when && f.image.width === w && f.image.height === h
    && viewText(f.view) === viewText(view) ? f.image.data : null;
}
function setLayers(key, base, above, view, w, h) {
  const toCanvas = toCanvasMap(view, w, h);
  warp.setBase(base, w, h);
  warp.setAbove(above);
  // the base has the sheet's geometry: canvas -> base pixel inverts device pixel -> canvas
  warp.setGeometry(toCanvas, [1 / toCanvas[0], 1 / toCanvas[1], -toCanvas[2] / toCanvas[0], -toCanvas[3] / toCanvas[1]]);
  ready = key;
}
// The layers of k, asked of the server one request at a time (the newest next).
async function ask(doc, k, t, view, w, h, key) {
  if (loading === key) return;
  wanted = {doc, k, t, view, w, h, key};
  if (loading) return;
  while (wanted) {
    const o = wanted; wanted = null;
    loading = o.key;
    try {
      const q = new URLSearchParams({k: o.k, t: o.t.toFixed(3), w: o.w, h: o.h, view: viewText(o.view)});
      const r = await api.post(`/api/layers?${q}`, o.doc);
      if (!r.ok) { failed = o.key; continue; }
      const raw = await r.arrayBuffer(), head = new DataView(raw);
      const bw = head.getUint32(0, true), bh = head.getUint32(4, true), n = bw * bh * 4;
      const above = head.getUint32(12, true) ? new Float32Array(raw, 16 + n, n) : null;
      if (bw === o.w && bh === o.h && canvas.width === bw && canvas.height === bh) {
        setLayers(o.key, new Uint8Array(raw, 16, n), above, o.view, bw, bh);
        again();
      }
    } catch (e) { failed = o.key; /* the server is away: the caller's frames go on */ }
    finally { loading = null; }
  }
}
// The layers of the selected op asked before a gesture needs them (its handles
// and sliders are what the hand takes next), and its programs warmed, at the time shown, when no
// gesture, play or solo is on (main.js runs this when the selection, the
// recipe, the size or the view change, not the time).
export function prefetchLayers(s) {
  const k = s.selected, doc = s.doc;
  if (k === null || !doc || !(k < doc.ops.length) || s.preview || s.playing || s.solo !== null || !s.screen) return;
  if (!s.info || s.info.mode === "live") return;
  const [w, h] = s.screen, view = viewOf(s), t = s.t;
  if (!available(w, h)) return;
  const key = keyOf(doc, k, t, t >= settledFrom(doc, k), view, w, h);
  if (ready !== key) ask(doc, k, t, view, w, h, key);
  // its programs compiled meanwhile (the top op's: also the one drawn before its layers come)
  const top = k === doc.ops.length - 1, edges = edgesOf(s, doc);
  warp.warm(doc.ops[k], t, edges, !top, top && ready !== key ? doc.ops[k] : null);
}
// Live mode: the newest live frame warped to the gesture's recipe ``now``, so the
// sheet answers a pointer move at once instead of after the session's next frame
// that shows it. ``frame``: {bitmap, w, h, doc, t, key}: the JPEG, the recipe it
// shows (the preview it was marbled with, or the saved one), the clock time it
// was marbled at and a key of its own; ``answer()``: the inputs the frame answers,
// asked only when it is drawn. Where ``now`` differs from ``frame.doc``
// in its top op only: a new op on top is walked back over the frame (the ops
// below it are what the frame shows); an op the frame shows as it was is taken
// off forward first (warp.js ``before``), and a stroke drawn further since is
// walked back over its new steps only (warp.js drawStrokeSince). Draws through
// ``draw(job, answer)`` as warpFrame does; false when it cannot (the caller
// shows the frame as it is): a recipe with ``motion``, whose motion strokes the
// session lays on top of every op, the gesture's too.
export function warpLive(s, now, frame, answer, draw) {
  if (s.view || !s.screen || !s.info || frame.t === null || now.motion !== undefined) return false;
  const [w, h] = s.screen, doc = frame.doc, k = now.ops.length - 1;
  if (k < 0 || changedOp(doc, now) !== k || !available(w, h)) return false;
  const op = now.ops[k], before = k < doc.ops.length ? doc.ops[k] : null, t = frame.t;
  const stroke = op.type === "stroke" && Array.isArray(op.times);
  if (before && !(stroke || lib.forwardable(op, before, t))) return false;
  const key = `live|${frame.key}|${w}x${h}`;
  if (ready !== key) {
    const {scale, offset, size} = s.info, sx = frame.w / size[0], sy = frame.h / size[1];
    warp.setBase(frame.bitmap, frame.w, frame.h);
    warp.setAbove(null);
    warp.setGeometry(toCanvasMap(viewOf(s), w, h), [scale * sx, scale * sy, offset[0] * sx, offset[1] * sy]);
    ready = key;
  }
  // a stroke drawn in time: as far as drawn (its newest point's time), the rest at the frame's
  const tNow = stroke ? Math.max(t, op.times[op.times.length - 1]) : t;
  const bg = doc.background === undefined ? "#ffffff" : doc.background, edges = edgesOf(s, doc);
  draw(() => {
    if (ready !== key) return null;  // a newer frame came: it is drawn instead
    const ok = before && stroke ? warp.drawStrokeSince(op, tNow, before, t, bg, edges)
      : warp.draw(op, tNow, bg, edges, before);
    return ok ? {read: (all) => warp.read(all), canvas, shown: {doc: now, t: +tNow.toFixed(3), w, h, view: viewOf(s), ops: null}} : null;
  }, answer());
  return true;
}

// Live mode: the programs a gesture of the chosen tool draws with (its op ``op``, as
// drawn over a frame without it and over one showing it as it was) compiled
// before the first gesture: SwiftShader compiles a program at its first draw
// (70-300 ms on two busy cores), which would be the gesture's first frame.
export function warmLive(s, op) {
  if (!s.screen || !s.doc || s.view) return;
  const [w, h] = s.screen;
  if (available(w, h)) warp.warm(op, s.t, edgesOf(s, s.doc), false, op);
}

// For tests and benchmarks: whether the page warps, and the layers it holds.
// (``interim``: the base is the exact frame with the op as it was, the layers on their way)
export const warpState = () => ({broken, ready: ready !== null, interim: !!ready && ready.startsWith("before|")});
