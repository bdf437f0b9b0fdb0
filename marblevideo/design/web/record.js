// What the sheet answered, for benchmarks and tests: every pointer input on the
// sheet (and every move of a parameter's slider) gets a sequence number and its
// time (the event's timeStamp, performance.now()'s clock); every frame drawn on
// the sheet appends to ``window.marbleFrames`` (the last LIMIT kept):
//   {n, input, inputAt, drawnAt, kind, w, h, ms}
// (a warped frame shown on the WebGL canvas: drawnAt is when its draw was seen
// done, at an animation frame, sheetgl.js; ``ms``: the page's time of its stages)
// ``input``: the newest input the frame answers (null: none, e.g. a reload);
// ``kind``: "warp" (drawn on the page), "server-draft" (not antialiased),
// "exact" (the server's exact render) or "live" (a live session's frame).
// ``window.marbleShown`` describes the last frame drawn: {doc, t, w, h, view, ops}
// (``ops``: the solo's op indices, or null), so that a script can compare the
// sheet with the server's exact render of the same recipe.
import { $ } from "./dom.js";

const LIMIT = 5000;
window.marbleFrames = [];
window.marbleShown = null;
let seq = 0, lastAt = null, claimed = 0, drawn = 0;

function onInput(ev) {
  if (ev.type === "pointermove" && !ev.buttons) return;  // a hover: no gesture handles it
  seq += 1;
  lastAt = ev.timeStamp || performance.now();
}
// The inputs so far: what a frame asked for now answers (the newest input not
// claimed before; null when none came since the last claim).
export function claimInput() {
  if (seq === claimed) return {input: null, inputAt: null};
  claimed = seq;
  return {input: seq, inputAt: lastAt};
}
// The newest input, claimed or not (a frame that shows the gesture as it is now).
export const newestInput = () => (seq ? {input: seq, inputAt: lastAt} : {input: null, inputAt: null});

export function recordFrame(kind, answer, w, h, shown) {
  drawn += 1;
  const frames = window.marbleFrames;
  const entry = {n: drawn, input: answer.input, inputAt: answer.inputAt, drawnAt: performance.now(), kind, w, h, ms: answer.ms};
  frames.push(entry);
  if (frames.length > LIMIT) frames.splice(0, frames.length - LIMIT);
  if (shown) window.marbleShown = shown;
  return entry;
}

export function initRecord() {
  const wrap = $("wrap");  // capture: numbered before the gesture handles the event
  for (const kind of ["pointerdown", "pointermove", "pointerup"]) wrap.addEventListener(kind, onInput, {capture: true});
  $("params").addEventListener("input", (ev) => { if (ev.target.type === "range") onInput(ev); }, {capture: true});
}
