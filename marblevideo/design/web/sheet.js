// The sheet: the frame drawn on a canvas, the overlay of handles and drags over
// it, and the geometry between them. The page's canvas has the frame's pixels;
// the recipe's canvas sits in it scaled by info.scale and offset by info.offset
// (the recipe format's geometry).
import * as api from "./api.js";
import { $, state, isLive, round1, setStatus, showError } from "./state.js";
import { tick } from "./timeline.js";

export const sheet = $("sheet"), overlay = $("overlay");
const ctx = sheet.getContext("2d"), octx = overlay.getContext("2d");

export function eventPixel(ev) {
  const r = overlay.getBoundingClientRect();
  return [(ev.clientX - r.left) * overlay.width / r.width, (ev.clientY - r.top) * overlay.height / r.height];
}
export function toCanvas([px, py]) {
  const {offset, scale} = state.info;
  return [round1((px - offset[0]) / scale), round1((py - offset[1]) / scale)];
}
export function toPixel([x, y]) {
  const {offset, scale} = state.info;
  return [x * scale + offset[0], y * scale + offset[1]];
}
// The sheet fills the space beside the panel (scaled up or down; its pixels stay the frame's).
export function fitSheet() {
  const k = Math.min((window.innerWidth - 370) / sheet.width, (window.innerHeight - 130) / sheet.height);
  sheet.style.width = `${Math.max(64, Math.floor(sheet.width * k))}px`;
}
export function resize([w, h]) {
  if (sheet.width !== w || sheet.height !== h) {
    sheet.width = overlay.width = w;
    sheet.height = overlay.height = h;
  }
  fitSheet();
}

// ---------------------------------------------------------------- rendering
let rendering = false, pending = null;
export const render = {committing: 0};  // saves on their way: renders wait for their answer
export const isRendering = () => rendering;
function visible(count) {
  return state.solo !== null && state.solo < count ? [state.solo] : null;
}
// Renders run one at a time, the newest request next, and wait while a save
// is on its way (its answer decides which recipe is shown).
export function show(opts = {}) {
  pending = opts;
  if (!rendering && !render.committing) drain();
}
async function drain() {
  rendering = true;
  while (pending && !render.committing) {
    const o = pending; pending = null;
    try { await renderOnce(o); } catch (e) { setStatus(`render: ${e}`); }
  }
  rendering = false;
  const {info} = state;
  if (state.playing || (info && info.input.kind === "live" && !state.gesture)) requestAnimationFrame(tick);
}
async function renderOnce(o) {
  if (isLive()) return liveFrame();
  const q = new URLSearchParams({t: state.t.toFixed(3)});
  if (o.draft) { q.set("draft", "1"); q.set("w", Math.max(64, Math.round(state.info.size[0] / 2))); }
  const body = o.doc || state.doc;
  const only = visible(body.ops.length);
  if (only !== null) q.set("ops", only.join(","));
  const started = performance.now(), shownVersion = state.version;
  // the page's own recipe, so what it shows never races a save or a reload
  const r = await api.frameOf(q, body);
  if (!r.ok) { if (!o.doc) showError((await r.json()).error); return; }
  const raw = await r.arrayBuffer(), head = new DataView(raw);
  const bitmap = new ImageData(new Uint8ClampedArray(raw, 8), head.getUint32(0, true), head.getUint32(4, true));
  if (bitmap.width === sheet.width && bitmap.height === sheet.height) ctx.putImageData(bitmap, 0, 0);
  else ctx.drawImage(await createImageBitmap(bitmap), 0, 0, sheet.width, sheet.height);
  state.frames += 1;
  sheet.dataset.frames = state.frames;
  sheet.dataset.draft = o.draft ? "1" : "0";
  sheet.dataset.version = o.doc ? "unsaved" : shownVersion;  // what the sheet shows
  sheet.dataset.shown = only === null ? "all" : only.join(",");
  setStatus(`${o.draft ? "draft" : "exact"} ${bitmap.width}x${bitmap.height} in ${(performance.now() - started).toFixed(0)} ms`);
  const g = state.gesture;
  if (g && !g.handle) drawHandles([g.a, g.b], g.label);  // a drag goes on
  else drawHandles();
}
// Live mode: the newest marbled frame, once one newer than the last shown has come.
async function liveFrame() {
  const r = await api.liveFrame(state.liveSeq);
  if (!r.ok) return;  // none yet (503 after 2 s): ask again
  state.liveSeq = Number(r.headers.get("X-Frame-Seq"));
  const bitmap = await createImageBitmap(await r.blob());
  ctx.drawImage(bitmap, 0, 0, sheet.width, sheet.height);
  bitmap.close();
  state.frames += 1;
  sheet.dataset.frames = state.frames;
  sheet.dataset.seq = state.liveSeq;
  if (!state.gesture) drawHandles();
}

// ---------------------------------------------------------------- handles
const lineWidth = () => Math.max(1.5, overlay.width / 500);
// The selected op's handles: its points (not motions) and every point of its paths.
export function pointsOf(i) {
  const op = state.doc.ops[i], found = [];
  if (!op || !state.types[op.type]) return found;
  for (const p of state.types[op.type].params) {
    const v = op[p.name];
    if (p.handle && Array.isArray(v)) found.push([p.name, v]);
    if (p.kind === "pointList" && Array.isArray(v)) found.push(...v.map((q, k) => [`${p.name}.${k}`, q]));
  }
  return found;
}
// "center", or "points.3": one point of a path, moved to ``at``.
export function setHandle(op, handle, at) {
  const [name, k] = handle.split(".");
  if (k === undefined) op[name] = at;
  else op[name][Number(k)] = at;
}
export function drawHandles(line, label = "") {
  octx.clearRect(0, 0, overlay.width, overlay.height);
  const w = lineWidth();
  octx.lineWidth = w;
  if (state.selected !== null) {
    for (const [, v] of pointsOf(state.selected)) {
      const [x, y] = toPixel(v);
      octx.strokeStyle = "#fff"; octx.fillStyle = "rgba(40,120,255,0.8)";
      octx.beginPath(); octx.arc(x, y, 4 * w, 0, 2 * Math.PI); octx.fill(); octx.stroke();
    }
  }
  if (line) {
    const [a, b] = line.map(toPixel);
    octx.strokeStyle = "rgba(255,255,255,0.8)"; octx.setLineDash([4 * w, 3 * w]);
    octx.beginPath(); octx.moveTo(a[0], a[1]); octx.lineTo(b[0], b[1]); octx.stroke();
    octx.setLineDash([]);
    octx.font = `${8 * w}px system-ui, sans-serif`;
    octx.strokeStyle = "rgba(0,0,0,0.8)"; octx.fillStyle = "#fff";
    octx.strokeText(label, b[0] + 6 * w, b[1] - 6 * w); octx.fillText(label, b[0] + 6 * w, b[1] - 6 * w);
  }
  overlay.dataset.label = line ? label : "";
}
export function drawPath(points) {
  const w = lineWidth();
  octx.strokeStyle = "rgba(255,255,255,0.8)"; octx.lineWidth = w; octx.setLineDash([4 * w, 3 * w]);
  octx.beginPath();
  points.map(toPixel).forEach(([x, y], k) => (k ? octx.lineTo(x, y) : octx.moveTo(x, y)));
  octx.stroke(); octx.setLineDash([]);
}
export function handleAt(px) {
  if (state.selected === null) return null;
  for (const [name, v] of pointsOf(state.selected)) {
    const [x, y] = toPixel(v);
    if (Math.hypot(x - px[0], y - px[1]) < 8 * lineWidth()) return name;
  }
  return null;
}
