// Undo and redo outlive a reload: the two stacks (whole recipes, as JSON) are
// kept in the browser's localStorage under the recipe file's full path and the
// page's mode, restored once the recipe is read and written whenever they
// change; at most LIMIT entries each. Where the browser will not keep them all
// (its quota), the oldest go first; where it keeps nothing, they last the page.
import { get, subscribe, update } from "./store.js";

const LIMIT = 100;
const keyOf = (info) => `marblevideo:history:${info.mode || "design"}:${info.path}`;

function read(key) {
  try {
    const kept = JSON.parse(localStorage.getItem(key) || "null");
    const ok = kept && Array.isArray(kept.undo) && Array.isArray(kept.redo);
    return ok ? kept : null;
  } catch {
    return null;  // storage off or unreadable: start empty
  }
}
function keep(s) {
  const key = keyOf(s.info);
  let undo = s.undo.slice(-LIMIT), redo = s.redo.slice(-LIMIT);
  for (;;) {
    try {
      localStorage.setItem(key, JSON.stringify({undo, redo}));
      return;
    } catch {
      if (!undo.length && !redo.length) return;
      if (undo.length >= redo.length) undo = undo.slice(1);
      else redo = redo.slice(1);
    }
  }
}
export function restoreHistory() {
  const kept = read(keyOf(get().info));
  if (kept) update(() => ({undo: kept.undo, redo: kept.redo}));
  subscribe((s) => [s.undo, s.redo], keep);
}
