// Live mode: the stroke being drawn goes to the live session (PUT
// /api/preview, marblevideo.design.live), which renders that unsaved recipe
// instead of the saved one until the save that follows the release. Up to
// FLIGHT sends on their way, each move's sent at once while fewer are, else the
// newest next (a drag's moves coalesce: newest wins); each names when it was
// sent (``sent``, ms), so one overtaken on the way is not shown (serial 0);
// while the hand holds still the newest is sent again every KEEP ms (the session drops a
// preview it has not heard of for a few seconds, so a page that goes away
// leaves none behind). A preview names the recipe version it was drawn on: once
// a save has made a newer one, the session ignores it.
// Each preview the session takes has a serial, and the live frames that show
// it carry it (X-Preview-Serial): :func:`previewAnswer` says which input such a
// frame shows (the newest when the preview was made), so the frames record the
// time from a pointer move to the live frame that shows it.
import * as api from "./api.js";
import { newestInput } from "./record.js";

const KEEP = 1500, FLIGHT = 2;
let newest = null, flying = 0, kept = null, timer = null;
const made = new Map();  // serial -> the input it shows (the newest at its making)

// The live clock's time at the press of event time ``stamp`` (ms,
// performance.now()'s clock), or null while it is paused (a stroke then has
// no times: it is applied whole as it grows). Asked of the session (POST
// /control with no change answers its state), the answer's time taken at the
// middle of the round trip.
export async function clockAtPress(stamp) {
  const asked = performance.now();
  const r = await api.control({}), state = await r.json(), mid = (asked + performance.now()) / 2;
  if (!r.ok || state.paused) return null;
  return Math.max(0, state.t - (mid - stamp) / 1000);
}
// Send the recipe ``make()`` gives (made once ``anchor``, a promise, is done)
// as drawn on recipe version ``version``.
export function sendPreview(make, version, anchor = null) {
  newest = {make, version, anchor};
  if (flying < FLIGHT) send();
}
async function send() {
  const p = newest;
  newest = null;
  flying += 1;
  try {
    if (p.anchor) await p.anchor;
    kept = {recipe: p.make(), version: p.version};
    const input = newestInput(), doc = kept.recipe;
    const r = await api.putPreview({...kept, sent: performance.timeOrigin + performance.now()});
    // (its serial read aside: the next send goes at once)
    if (r.ok) r.json().then(({serial}) => { if (serial) made.set(serial, {...input, doc}); }).catch(() => {});
    if (made.size > 256) made.delete(made.keys().next().value);
  } catch (e) { /* the next move sends again */ }
  flying -= 1;
  if (newest) { send(); return; }
  if (flying) return;
  clearTimeout(timer);
  if (kept) timer = setTimeout(() => { if (kept && !newest) sendPreview(() => kept.recipe, kept.version); }, KEEP);
}
// The input a live frame tagged with preview ``serial`` shows (none when unknown;
// the sheet counts each input once).
export function previewAnswer(serial) {
  const m = made.get(serial);
  return m ? {input: m.input, inputAt: m.inputAt} : {input: null, inputAt: null};
}
// The recipe of the preview ``serial`` (null when unknown).
export const previewDoc = (serial) => (made.get(serial) || {doc: null}).doc;
// The gesture is over: nothing more is sent; ``version`` (a cancel): the
// session drops the preview now (null: a save is on its way and replaces it).
export function clearPreview(version) {
  newest = null; kept = null;
  clearTimeout(timer);
  if (version !== null) api.putPreview({recipe: null, version, sent: performance.timeOrigin + performance.now()}).catch(() => {});
}
