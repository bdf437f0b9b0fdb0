// The sheet: frames drawn on a canvas of the sheet's displayed size in device
// pixels, of the window of the recipe's canvas that the view shows (view.js).
// Renders follow the store (``showSheet``, a view): the saved recipe, or the
// preview of one not saved (a gesture, a slider). During a gesture the page
// warps an exact picture of the ops below the changing op (warping.js, WebGL2);
// otherwise, and where it cannot, the server renders: its exact render (for a
// heavy design a quick frame without antialiasing first), or while a hand moves
// frames without antialiasing, the newest request next. A frame is drawn in
// requestAnimationFrame, over the last one: the sheet is never blank.
import * as api from "./api.js";
import { hexColor } from "./dom.js";
import { claimInput, newestInput, recordFrame } from "./record.js";
import { previewAnswer, previewDoc } from "./livepreview.js";
import { enabled as glSheet, gpuBusy, hideWarp, settleWarp, shownPixels, showWarp, whenDrawn } from "./sheetgl.js";
import { get, update, isLive } from "./store.js";
import { eventPixel, fitSheet, overlay, sheet, sizeOf, toCanvas, toCanvasMap, toPixel, viewOf } from "./view.js";
import { changedOp, warpFrame, warpLive, whenLayers } from "./warping.js";

export { eventPixel, fitSheet, overlay, sheet, sizeOf, toCanvas, toPixel };
const ctx = sheet.getContext("2d");

// The canvases take the sheet's device size; the last frame is kept, scaled, until the next comes.
export const screenOf = (s) => [s.info.size, s.screen];
export function resize(s) {
  fitSheet();
  if (!s.screen) return;
  const [w, h] = s.screen;
  if (sheet.width === w && sheet.height === h) return;
  settleWarp();
  const keep = frames ? copyOf(sheet) : null;
  sheet.width = overlay.width = w;
  sheet.height = overlay.height = h;
  if (keep) ctx.drawImage(keep, 0, 0, w, h);
  else ground(s);
}
function copyOf(canvas) {
  const c = document.createElement("canvas");
  c.width = canvas.width; c.height = canvas.height;
  c.getContext("2d").drawImage(canvas, 0, 0);
  return c;
}
// Before the first frame: the recipe's ground colour, never black.
function ground(s) {
  const bg = s.doc && s.doc.background;
  try { ctx.fillStyle = bg && (typeof bg === "string" || Array.isArray(bg)) ? hexColor(bg) : "#ffffff"; }
  catch (e) { ctx.fillStyle = "#ffffff"; }
  ctx.fillRect(0, 0, sheet.width, sheet.height);
}

// ---------------------------------------------------------------- what is shown
let rendering = false, pending = null, frames = 0, liveSeq = 0, liveAnswered = 0, idle = () => {};
// exactMs: the last exact render's time (a slow one makes the next progressive);
// stamps: what was asked later is drawn later
let exactMs = null, stamp = 0, drawnStamp = 0;
export const isRendering = () => rendering;
// ``fn`` runs each time the renders asked for are done (main.js: the clock's next tick).
export function whenIdle(fn) { idle = fn; }
// What the sheet shows: the recipe, its time and solo, the preview, the view and
// size; live mode: the recipe only.
export const sheetOf = (s) => (isLive(s) ? [s.doc, s.version, s.saving, s.screen]
  : [s.doc, s.version, s.saving, s.preview, s.solo, s.t, s.playing, s.view, s.screen]);
export function showSheet(s, inputs = claimInput()) {
  if (!s.screen) return;
  const answer = {...inputs, stamp: ++stamp};
  if (s.preview && s.preview.draft && !isLive(s) && s.solo === null) {
    const k = changedOp(s.doc, s.preview.doc);
    if (k === "same" && frames) return;
    if (k !== "same" && k !== null && warpFrame(s, k, answer, drawWarp, lastExact, shownWarp)) return;
  }
  show(s.preview ? {draft: s.preview.draft, doc: s.preview.doc} : {draft: s.playing}, answer);
}
// (the gesture's frame once its layers come shows the newest input, answered before or not)
whenLayers(() => { if (get().preview) showSheet(get(), newestInput()); });
// Renders run one at a time, the newest request next, and wait while a save
// is on its way (its answer decides which recipe is shown).
export function show(opts = {}, answer = {...claimInput(), stamp: ++stamp}) {
  const s = get();
  pending = {...opts, ...carried(pending && {answer: pending}, answer), view: viewOf(s), size: s.screen || s.info.size};
  if (!rendering && !s.saving) drain();
}
async function drain() {
  rendering = true;
  while (pending && !get().saving) {
    const o = pending; pending = null;
    try {
      if (!o.draft && !o.doc && !isLive() && (frames === 0 || (exactMs > 150 && lastKind !== "warp"))) {
        await renderOnce({...o, draft: true, quick: true});  // progressive: a quick frame first
        if (pending) continue;
      }
      await renderOnce(o);
    } catch (e) { update(() => ({status: `render: ${e}`})); }
  }
  rendering = false;
  idle();
}
function visible(s, count) {
  return s.solo !== null && s.solo < count ? [s.solo] : null;
}
export const viewParam = (view) => view.map((v) => +v.toFixed(6)).join(",");
async function renderOnce(o) {
  if (isLive()) return liveFrame(o);
  const s = get(), [w, h] = o.size;
  const q = new URLSearchParams({t: s.t.toFixed(3), w, h, view: viewParam(o.view)});
  if (o.draft) q.set("draft", "1");
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
  const image = new ImageData(new Uint8ClampedArray(raw, 8), head.getUint32(0, true), head.getUint32(4, true));
  const took = performance.now() - started;
  if (!o.draft) exactMs = took;
  const frame = {image, kind: o.draft ? "server-draft" : "exact", answer: o, doc: body, t: Number(q.get("t")),
    view: o.view, only, version: o.doc ? "unsaved" : shownVersion};
  await drawn(frame);
  update(() => ({status: `${o.draft ? "draft" : "exact"} ${image.width}x${image.height} in ${took.toFixed(0)} ms`}));
}

// ---------------------------------------------------------------- drawing
let lastKind = null, lastExact = null, lastWarp = null, waiting = null, warpJob = null, raf = 0;
// The sheet's picture when its last frame was warped ({doc, t, w, h, view, image}), else null:
// the next gesture's base while the exact frame of a heavy design is on its way.
const shownWarp = () => (lastKind === "warp" && lastWarp
  ? {...lastWarp, image: shownPixels()} : null);
function schedule() { if (!raf) raf = requestAnimationFrame(paint); }
// A server frame, drawn at the next animation frame (resolves once drawn).
function drawn(frame) {
  return new Promise((resolve) => {
    if (waiting) waiting.resolve();
    waiting = {frame, resolve};
    schedule();
  });
}
// A warp frame: ``job()`` draws it into a canvas of the sheet's size, or says it cannot.
function drawWarp(job, answer) { warpJob = Object.assign(job, {answer: carried(warpJob, answer)}); schedule(); }
// The answer of a frame that replaces one not drawn: the inputs the older one claimed are its too.
function carried(older, answer) {
  const a = older && older.answer;
  return a && a.input !== null && (answer.input === null || answer.input < a.input)
    ? {...answer, input: a.input, inputAt: a.inputAt} : answer;
}
function paint() {
  raf = 0;
  if (warpJob && glSheet && gpuBusy()) schedule();  // the newest job waits for the GPU's last frame
  else if (warpJob) {
    const job = warpJob; warpJob = null;
    const t0 = performance.now();
    const done = job.answer.stamp >= drawnStamp ? job() : undefined;  // undefined: stale
    if (done) {
      // only what changed since the warp's last frame, when that is what the sheet shows
      const t1 = performance.now();
      const gpu = glSheet && done.canvas;
      if (gpu) showWarp(done.canvas, done.read);  // shown as it is: no readback
      else {
        const {image, rect} = done.read(lastKind !== "warp");
        if (rect[2] > 0 && rect[3] > 0) ctx.putImageData(image, 0, 0, ...rect);
      }
      job.answer.ms = [t1 - t0, performance.now() - t1];
      const live = isLive(), answer = live ? answered(job.answer) : job.answer;  // (live: each input once)
      const entry = note(live ? "live-warp" : "warp", answer, done.shown);
      if (gpu) whenDrawn(entry);
      lastWarp = done.shown;
    }
    else if (done === null && !isLive()) show({draft: true, doc: get().preview ? get().preview.doc : null}, job.answer);
  }
  if (waiting) {
    const {frame, resolve} = waiting; waiting = null;
    const {image} = frame;
    if (frame.kind === "exact" && frame.only === null && frame.version !== "unsaved") lastExact = frame;
    // a warp frame asked later is shown, or the sheet has another size since (its
    // last frame is kept, scaled, and a frame of the new size is on its way)
    if (frame.answer.stamp < drawnStamp || image.width !== sheet.width || image.height !== sheet.height) {
      resolve();
      return;
    }
    ctx.putImageData(image, 0, 0);
    hideWarp();
    sheet.dataset.draft = frame.kind === "exact" ? "0" : "1";
    sheet.dataset.version = frame.version;  // what the sheet shows
    sheet.dataset.shown = frame.only === null ? "all" : frame.only.join(",");
    note(frame.kind, frame.answer, {doc: frame.doc, t: frame.t, w: image.width, h: image.height,
      view: frame.view, ops: frame.only});
    resolve();
  }
}
function note(kind, answer, shown) {
  frames += 1;
  drawnStamp = Math.max(drawnStamp, answer.stamp || 0);
  lastKind = kind;
  sheet.dataset.frames = frames;
  sheet.dataset.kind = kind;
  if (kind === "warp") sheet.dataset.draft = "1";
  return recordFrame(kind, answer, sheet.width, sheet.height, shown);
}
// Live mode: the newest marbled frame, once one newer than the last shown has
// come. The next is asked for as soon as one comes (the session answers it when
// a newer JPEG is made), so it is on its way while this one is decoded and drawn.
let liveNext = null;  // {after, reply}: the request for the frame after liveSeq
function liveReply(after) {
  const next = liveNext && liveNext.after === after ? liveNext.reply : api.liveFrame(after);
  liveNext = null;
  return next;
}
async function liveFrame(o) {
  const r = await liveReply(liveSeq);
  if (r.status === 204 || !r.ok) return;  // none yet (204 No Content after 2 s): ask again
  liveSeq = Number(r.headers.get("X-Frame-Seq"));
  liveNext = {after: liveSeq, reply: api.liveFrame(liveSeq)};
  liveNext.reply.catch(() => {});  // (a failure is met when it is awaited)
  // A frame showing a preview answers the input the preview was made after (once);
  // mid-gesture, one without shows the saved recipe: no input. Each input once.
  const serial = Number(r.headers.get("X-Preview-Serial") || 0), time = r.headers.get("X-Frame-Time");
  if (serial) o = {...o, ...previewAnswer(serial)};
  else if (get().gesture) o = {...o, input: null, inputAt: null};
  const bitmap = await createImageBitmap(await r.blob());
  const doc = serial ? previewDoc(serial) : get().doc;
  if (liveBase) liveBase.bitmap.close();
  liveBase = {bitmap, w: bitmap.width, h: bitmap.height, doc, t: time === null ? null : Number(time), key: liveSeq};
  sheet.dataset.seq = liveSeq;
  // mid-gesture, the frame warped to the gesture as it is now (it answers the newest input)
  if (liveDraft && doc && warpLive(get(), liveDraft, liveBase, () => liveAnswer(newestInput()), drawWarp)) return;
  o = answered(o);
  await new Promise((resolve) => requestAnimationFrame(() => {
    warpJob = null;  // (a warp of an older frame not drawn yet: this one is newer)
    ctx.drawImage(bitmap, 0, 0, sheet.width, sheet.height);
    hideWarp();
    resolve();
  }));
  note("live", o, null);
}
// Live mode: the newest live frame ({bitmap, w, h, doc, t, key}: warping.js warpLive)
// and the recipe of the gesture under way (null: none).
let liveBase = null, liveDraft = null;
// An answer of a live frame, counted once per input (a later frame showing an input
// already answered answers none).
function answered(o) {
  if (o.input !== null && o.input <= liveAnswered) return {...o, input: null, inputAt: null};
  if (o.input !== null) liveAnswered = o.input;
  return o;
}
// The answer of a live frame the page warps (asked only when it draws one; counted
// once per input when it is drawn: a warp not drawn leaves its input to the next frame).
const liveAnswer = (inputs) => ({...inputs, stamp: ++stamp});
// Live mode, a gesture's recipe as it is now (``doc``; null: the gesture is over):
// the newest live frame warped to it at once, where the page can (warping.js warpLive);
// the frames the session marbles with it follow.
export function liveGesture(doc) {
  liveDraft = doc;
  if (!doc) warpJob = null;
  if (doc && liveBase && liveBase.doc) warpLive(get(), doc, liveBase, () => liveAnswer(claimInput()), drawWarp);
}
// The geometry of the frame shown now: device pixel -> canvas ([sx, sy, ox, oy]).
export const shownMap = () => toCanvasMap(viewOf(), sheet.width, sheet.height);
