// Live mode: the stroke being drawn goes to the live session (PUT
// /api/preview, marblevideo.design.live), which renders that unsaved recipe
// instead of the saved one until the save that follows the release. One send
// at a time, the newest next (a drag's moves coalesce: newest wins); while the
// hand holds still the newest is sent again every KEEP ms (the session drops a
// preview it has not heard of for a few seconds, so a page that goes away
// leaves none behind). A preview names the recipe version it was drawn on: once
// a save has made a newer one, the session ignores it.
import * as api from "./api.js";

const KEEP = 1500;
let newest = null, sending = false, kept = null, timer = null;

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
  if (!sending) pump();
}
async function pump() {
  sending = true;
  while (newest) {
    const p = newest;
    newest = null;
    if (p.anchor) await p.anchor;
    kept = {recipe: p.make(), version: p.version};
    try { await api.putPreview(kept); } catch (e) { /* the next move sends again */ }
  }
  sending = false;
  clearTimeout(timer);
  if (kept) timer = setTimeout(() => { if (kept && !newest) sendPreview(() => kept.recipe, kept.version); }, KEEP);
}
// The gesture is over: nothing more is sent; ``version`` (a cancel): the
// session drops the preview now (null: a save is on its way and replaces it).
export function clearPreview(version) {
  newest = null; kept = null;
  clearTimeout(timer);
  if (version !== null) api.putPreview({recipe: null, version}).catch(() => {});
}
