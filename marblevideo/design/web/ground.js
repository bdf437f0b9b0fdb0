// The ground colour field (the recipe's background at the time shown): a view
// of the store; a change saves it through edits.setGround.
import { $, hexColor } from "./dom.js";
import { setGround } from "./edits.js";
import { isTrack } from "./values.js";

// A constant colour as it is (white where none is given); a track's key at or
// before ``t`` (the field shows a key's colour, not the blend between two).
function groundAt(v, t) {
  if (!isTrack(v)) return v ?? "#ffffff";
  const before = v.keys.filter((k) => k.t <= t);
  return (before.length ? before.at(-1) : v.keys[0]).v;
}
export const groundOf = (s) => [s.doc && s.doc.background, s.t];
export function showGround(s) {
  if (s.doc) $("ground").value = hexColor(groundAt(s.doc.background, s.t));
}
export function initGround() {
  $("ground").addEventListener("change", () => setGround($("ground").value));
}
