// The pointer on the sheet: its events routed to the gesture under way
// (gestures.js). Input that comes before the page has its recipe (a click as
// the page appears) is kept, as fractions of the sheet, and replayed once it
// has; the sheet shows a progress cursor meanwhile. Each event goes with its
// device pixel and time stamp (a timed stroke's points and times: stylus.js).
import { gesture } from "./gestures.js";
import { eventPixel, overlay, toCanvas } from "./sheet.js";
import { get } from "./store.js";

let early = [], earlyDown = false;

function capture(pointerId) {
  try { overlay.setPointerCapture(pointerId); } catch (e) { /* the pointer is up already */ }
}
function onPointer(kind, handler) {
  overlay.addEventListener(kind, (ev) => {
    if (document.body.dataset.ready === "1") { handler(ev); return; }
    if (kind === "pointerdown" && ev.button === 0) { earlyDown = true; capture(ev.pointerId); }
    if (kind === "pointermove" && !earlyDown) return;  // a hover: nothing to replay
    if (kind !== "pointermove") earlyDown = kind === "pointerdown" && ev.button === 0;
    const r = overlay.getBoundingClientRect();
    early.push({handler, type: ev.type, button: ev.button, pointerId: ev.pointerId, altKey: ev.altKey,
      timeStamp: ev.timeStamp, fx: (ev.clientX - r.left) / r.width, fy: (ev.clientY - r.top) / r.height});
  });
}
export function replayEarly() {
  const r = overlay.getBoundingClientRect();
  for (const e of early.splice(0)) {
    e.handler({type: e.type, button: e.button, pointerId: e.pointerId, altKey: e.altKey, timeStamp: e.timeStamp,
      clientX: r.left + e.fx * r.width, clientY: r.top + e.fy * r.height});
  }
}
const canvasPoint = (ev) => toCanvas(eventPixel(ev));
// What a gesture takes of an event besides its point: Alt, the device pixel, the time stamp (ms).
const detail = (ev) => ({alt: ev.altKey, stamp: ev.timeStamp ?? performance.now(),
  dev: [ev.clientX * devicePixelRatio, ev.clientY * devicePixelRatio]});
// The moves the browser coalesced into this event (a stylus reports faster
// than frames are drawn), each as a gesture takes it: [at, detail]; [] if none.
function samples(ev) {
  const list = ev.getCoalescedEvents ? ev.getCoalescedEvents() : [];
  return list.length > 1 ? list.map((e) => [canvasPoint(e), detail(e)]) : [];
}
function down(ev) {
  if (!get().doc || ev.button !== 0) return;
  capture(ev.pointerId);
  const px = eventPixel(ev);
  gesture.down(toCanvas(px), px, detail(ev));
}
const up = (ev) => (ev.type === "pointerup" ? gesture.up(canvasPoint(ev), detail(ev)) : gesture.cancel());

export function initPointer() {
  onPointer("pointerdown", down);
  onPointer("pointermove", (ev) => gesture.move(canvasPoint(ev), {...detail(ev), samples: samples(ev)}));
  onPointer("pointerup", up);
  onPointer("pointercancel", up);
}
