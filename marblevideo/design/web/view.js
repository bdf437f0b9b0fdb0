// The sheet's geometry: its canvases at their displayed size in device pixels
// (CSS size x devicePixelRatio, followed by a ResizeObserver: the store's
// ``screen``), and the window of the recipe's canvas they show (the store's
// ``view``: [x, y, w, h] in canvas units, fitted uniformly and centred as the
// server's ``view`` is; null: the frame's own area). Zoom (the wheel at the
// pointer, + and -, 0 resets) and pan (a drag with Space held or the middle
// button, the arrow keys) change the view; the sheet renders it exactly.
// A "pixel" here is a device pixel of the sheet: (0, 0) its top-left corner.
import { $, isField } from "./dom.js";
import { get, update } from "./store.js";
import { round1 } from "./values.js";

export const sheet = $("sheet"), overlay = $("overlay");

// The frame's area in canvas units (the view of an unzoomed sheet).
export function frameView(info) {
  const {offset, scale, size} = info;
  return [-offset[0] / scale, -offset[1] / scale, size[0] / scale, size[1] / scale];
}
export const viewOf = (s = get()) => s.view || frameView(s.info);
// Device pixels per canvas unit and the view's offset in a w x h sheet: [k, dx, dy].
export function fitOf(view, w, h) {
  const k = Math.min(w / view[2], h / view[3]);
  return [k, (w - k * view[2]) / 2, (h - k * view[3]) / 2];
}
// Device pixel -> canvas as [sx, sy, ox, oy] (canvas = pixel * s + o), the server's to_canvas.
export function toCanvasMap(view, w, h) {
  const [k, dx, dy] = fitOf(view, w, h);
  return [1 / k, 1 / k, view[0] - dx / k, view[1] - dy / k];
}
function current() {
  const s = get();
  return fitOf(viewOf(s), sheet.width, sheet.height).concat([viewOf(s)]);
}
export function toCanvas([px, py]) {
  const [k, dx, dy, v] = current();
  return [round1((px - dx) / k + v[0]), round1((py - dy) / k + v[1])];
}
export function toPixel([x, y]) {
  const [k, dx, dy, v] = current();
  return [(x - v[0]) * k + dx, (y - v[1]) * k + dy];
}
export function eventPixel(ev) {
  const r = overlay.getBoundingClientRect();
  return [(ev.clientX - r.left) * overlay.width / r.width, (ev.clientY - r.top) * overlay.height / r.height];
}

// ---------------------------------------------------------------- size
// The sheet's CSS box: the frame's aspect, as large as the stage allows.
export function fitSheet() {
  const s = get();
  if (!s.info) return;
  const [w, h] = s.info.size, stage = $("stage");
  const k = Math.min((stage.clientWidth - 20) / w, (stage.clientHeight - 20) / h);
  let cssW = Math.max(64, Math.floor(w * k));
  for (let c = cssW; c > Math.max(64, cssW - 64); c--) {  // a width whose height is whole: the frame's aspect exactly
    if (Number.isInteger(c * h / w)) { cssW = c; break; }
  }
  sheet.style.width = `${cssW}px`;
  sheet.style.height = `${Math.max(16, Math.round(h * cssW / w))}px`;
}
export const sizeOf = (s) => s.info.size;
function observed(entry) {
  // the device-pixel box where it is the CSS box x devicePixelRatio (snapped);
  // an emulated ratio (headless) leaves it at CSS pixels: then the product
  const dpr = window.devicePixelRatio || 1, css = entry.contentRect;
  const box = entry.devicePixelContentBoxSize && entry.devicePixelContentBoxSize[0];
  const near = (v, c) => Math.abs(v - c * dpr) <= 1.5;
  const exact = box && near(box.inlineSize, css.width) && near(box.blockSize, css.height);
  const w = exact ? box.inlineSize : Math.round(css.width * dpr);
  const h = exact ? box.blockSize : Math.round(css.height * dpr);
  const now = get().screen;
  if (w > 0 && h > 0 && (!now || now[0] !== w || now[1] !== h)) update(() => ({screen: [w, h]}));
}
export function initSize() {
  new ResizeObserver((entries) => entries.forEach(observed)).observe(sheet);
  new ResizeObserver(fitSheet).observe($("stage"));  // the window, or what shares the stage (an error shown)
}

// ---------------------------------------------------------------- zoom and pan
const MIN_SIDE = 2;  // the smallest view side, in canvas units
function setView(v) {
  const full = frameView(get().info), big = 16 * Math.max(full[2], full[3]);
  if (v[2] < MIN_SIDE || v[3] < MIN_SIDE || v[2] > big || v[3] > big) return;
  update(() => ({view: v}));
}
// Zoom by ``factor`` (> 1: closer) about device pixel px (default: the centre).
export function zoomAt(factor, px = [sheet.width / 2, sheet.height / 2]) {
  const v = viewOf(), [k, dx, dy] = fitOf(v, sheet.width, sheet.height);
  const cx = (px[0] - dx) / k + v[0], cy = (px[1] - dy) / k + v[1];
  setView([cx - (cx - v[0]) / factor, cy - (cy - v[1]) / factor, v[2] / factor, v[3] / factor]);
}
// Pan by (ddx, ddy) device pixels (the picture follows the hand).
export function panBy(ddx, ddy) {
  const v = viewOf(), [k] = fitOf(v, sheet.width, sheet.height);
  setView([v[0] - ddx / k, v[1] - ddy / k, v[2], v[3]]);
}
export const resetView = () => update(() => ({view: null}));

const KEYS = {
  "+": () => zoomAt(1.25), "=": () => zoomAt(1.25), "-": () => zoomAt(0.8), "_": () => zoomAt(0.8),
  "0": resetView,
  ArrowLeft: () => panBy(sheet.width / 10, 0), ArrowRight: () => panBy(-sheet.width / 10, 0),
  ArrowUp: () => panBy(0, sheet.height / 10), ArrowDown: () => panBy(0, -sheet.height / 10),
};
// Space held is the keyboard's state, wherever the focus is: a field keeps its
// key (a space typed, a colour chooser's), and a press on the sheet while it is
// held pans and takes the focus from the field, so the keys after it are the page's.
let space = false, panning = null;
function onKey(ev) {
  if (ev.key === " ") {
    if (!ev.repeat) space = ev.type === "keydown";
    if (!isField(ev.target)) ev.preventDefault();  // the page does not scroll
    return;
  }
  if (isField(ev.target)) return;
  if (ev.type !== "keydown" || ev.ctrlKey || ev.metaKey || ev.altKey || !KEYS[ev.key] || !get().info) return;
  ev.preventDefault();
  KEYS[ev.key]();
}
// A press with Space held or the middle button pans; it never reaches the gestures.
function onPointer(ev) {
  if (ev.type === "pointerdown" && (ev.button === 1 || (ev.button === 0 && space))) {
    if (isField(document.activeElement)) document.activeElement.blur();
    panning = {id: ev.pointerId, at: eventPixel(ev)};
    overlay.setPointerCapture(ev.pointerId);
  } else if (!panning || ev.pointerId !== panning.id) return;
  else if (ev.type === "pointermove") {
    const at = eventPixel(ev);
    panBy(at[0] - panning.at[0], at[1] - panning.at[1]);
    panning.at = at;
  } else if (ev.type === "pointerup" || ev.type === "pointercancel") panning = null;
  ev.stopPropagation();
}
function onWheel(ev) {
  if (!get().info) return;
  ev.preventDefault();
  zoomAt(Math.exp(-ev.deltaY * (ev.deltaMode === 1 ? 0.05 : 0.002)), eventPixel(ev));
}
export function initView() {
  document.addEventListener("keydown", onKey);
  document.addEventListener("keyup", onKey);
  window.addEventListener("blur", () => { space = false; });  // its keyup goes to another window
  const wrap = $("wrap");
  for (const kind of ["pointerdown", "pointermove", "pointerup", "pointercancel"]) {
    wrap.addEventListener(kind, onPointer, {capture: true});
  }
  overlay.addEventListener("wheel", onWheel, {passive: false});
  overlay.addEventListener("auxclick", (ev) => ev.preventDefault());
}
