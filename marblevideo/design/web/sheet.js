// The sheet: the frame drawn on a canvas, and the geometry between the frame
// and the recipe's canvas. The page's canvas has the frame's pixels; the
// recipe's canvas sits in it scaled by info.scale and offset by info.offset
// (the recipe format's geometry). Renders follow the store (``showSheet``, a
// view): the saved recipe, or the preview of one not saved (a gesture, a slider).
import * as api from "./api.js";
import { $ } from "./dom.js";
import { get, update, isLive } from "./store.js";
import { round1 } from "./values.js";

export const sheet = $("sheet"), overlay = $("overlay");
const ctx = sheet.getContext("2d");

export function eventPixel(ev) {
  const r = overlay.getBoundingClientRect();
  return [(ev.clientX - r.left) * overlay.width / r.width, (ev.clientY - r.top) * overlay.height / r.height];
}
export function toCanvas([px, py]) {
  const {offset, scale} = get().info;
  return [round1((px - offset[0]) / scale), round1((py - offset[1]) / scale)];
}
export function toPixel([x, y]) {
  const {offset, scale} = get().info;
  return [x * scale + offset[0], y * scale + offset[1]];
}
// The sheet fills the space beside the panel (scaled up or down; its pixels stay the frame's).
export function fitSheet() {
  const k = Math.min((window.innerWidth - 370) / sheet.width, (window.innerHeight - 130) / sheet.height);
  sheet.style.width = `${Math.max(64, Math.floor(sheet.width * k))}px`;
}
export const sizeOf = (s) => s.info.size;
export function resize(s) {
  const [w, h] = s.info.size;
  if (sheet.width !== w || sheet.height !== h) {
    sheet.width = overlay.width = w;
    sheet.height = overlay.height = h;
  }
  fitSheet();
}

// ---------------------------------------------------------------- rendering
let rendering = false, pending = null, frames = 0, liveSeq = 0, idle = () => {};
export const isRendering = () => rendering;
// ``fn`` runs each time the renders asked for are done (main.js: the clock's next tick).
export function whenIdle(fn) { idle = fn; }
// What the sheet shows: the recipe, its time and solo, the preview; live mode: the recipe only.
export const sheetOf = (s) => (isLive(s) ? [s.doc, s.version, s.saving]
  : [s.doc, s.version, s.saving, s.preview, s.solo, s.t, s.playing]);
export function showSheet(s) {
  show(s.preview ? {draft: s.preview.draft, doc: s.preview.doc} : {draft: s.playing});
}
// Renders run one at a time, the newest request next, and wait while a save
// is on its way (its answer decides which recipe is shown).
export function show(opts = {}) {
  pending = opts;
  if (!rendering && !get().saving) drain();
}
async function drain() {
  rendering = true;
  while (pending && !get().saving) {
    const o = pending; pending = null;
    try { await renderOnce(o); } catch (e) { update(() => ({status: `render: ${e}`})); }
  }
  rendering = false;
  idle();
}
function visible(s, count) {
  return s.solo !== null && s.solo < count ? [s.solo] : null;
}
async function renderOnce(o) {
  if (isLive()) return liveFrame();
  const s = get(), q = new URLSearchParams({t: s.t.toFixed(3)});
  if (o.draft) { q.set("draft", "1"); q.set("w", Math.max(64, Math.round(s.info.size[0] / 2))); }
  const body = o.doc || s.doc;
  const only = visible(s, body.ops.length);
  if (only !== null) q.set("ops", only.join(","));
  const started = performance.now(), shownVersion = s.version;
  // the page's own recipe, so what it shows never races a save or a reload
  const r = await api.frameOf(q, body);
  if (!r.ok) {
    const {error} = await r.json();
    if (!o.doc) update(() => ({error}));
    return;
  }
  const raw = await r.arrayBuffer(), head = new DataView(raw);
  const bitmap = new ImageData(new Uint8ClampedArray(raw, 8), head.getUint32(0, true), head.getUint32(4, true));
  if (bitmap.width === sheet.width && bitmap.height === sheet.height) ctx.putImageData(bitmap, 0, 0);
  else ctx.drawImage(await createImageBitmap(bitmap), 0, 0, sheet.width, sheet.height);
  frames += 1;
  sheet.dataset.frames = frames;
  sheet.dataset.draft = o.draft ? "1" : "0";
  sheet.dataset.version = o.doc ? "unsaved" : shownVersion;  // what the sheet shows
  sheet.dataset.shown = only === null ? "all" : only.join(",");
  const took = (performance.now() - started).toFixed(0);
  update(() => ({status: `${o.draft ? "draft" : "exact"} ${bitmap.width}x${bitmap.height} in ${took} ms`}));
}
// Live mode: the newest marbled frame, once one newer than the last shown has come.
async function liveFrame() {
  const r = await api.liveFrame(liveSeq);
  if (!r.ok) return;  // none yet (503 after 2 s): ask again
  liveSeq = Number(r.headers.get("X-Frame-Seq"));
  const bitmap = await createImageBitmap(await r.blob());
  ctx.drawImage(bitmap, 0, 0, sheet.width, sheet.height);
  bitmap.close();
  frames += 1;
  sheet.dataset.frames = frames;
  sheet.dataset.seq = liveSeq;
}
