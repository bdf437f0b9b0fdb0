// What the op list and the editors do to the recipe and the selection: each
// changes the store (the selection, the solo) or saves an edit (recipe.js).
import { edited } from "./recipe.js";
import { get, update } from "./store.js";
import { isTrack, round3 } from "./values.js";

export const select = (i) => update(() => ({selected: i}));
export const toggleSolo = (i) => update((s) => ({solo: s.solo === i ? null : i}));
export function move(i, step) {
  const j = i + step;
  if (j < 0 || j >= get().doc.ops.length) return;
  if (get().selected === i) select(j);
  edited((d) => { [d.ops[i], d.ops[j]] = [d.ops[j], d.ops[i]]; });
}
// Hide is saved: "hidden": true keeps the op in the file and out of every render.
export function toggleHidden(i) {
  edited((d) => { if (d.ops[i].hidden) delete d.ops[i].hidden; else d.ops[i].hidden = true; });
}
export function remove(i) {
  update(({selected, solo}) => ({
    selected: selected !== null && selected >= i ? (selected === i ? null : selected - 1) : selected,
    solo: solo === i ? null : solo,
  }));
  edited((d) => { d.ops.splice(i, 1); });
}
// Clear: every op removed in one edit (undoable); nothing stays selected.
export function clearOps() {
  update(() => ({selected: null, solo: null}));
  return edited((d) => { d.ops = []; });
}
// The ground: the recipe's background set to ``value``; keyed at the time shown
// where the background is a keyframe track.
export function setGround(value) {
  if (get().doc.background === value) return Promise.resolve(false);  // nothing to undo
  return edited((d) => { d.background = isTrack(d.background) ? keyed(d.background, value, get().t) : value; });
}
// Parameter ``name`` of op i set to ``value`` (undefined: removed, its default).
export function setParam(i, name, value) {
  return edited((d) => { if (value === undefined) delete d.ops[i][name]; else d.ops[i][name] = value; });
}
// ``old`` (a value or keys) with a key of value v at time t.
export function keyed(old, v, t) {
  const keys = isTrack(old) ? old.keys.filter((k) => Math.abs(k.t - t) > 1e-6)
    : (old === undefined || t === 0 ? [] : [{t: 0, v: old}]);
  keys.push({t: round3(t), v});
  keys.sort((x, y) => x.t - y.t);
  return {keys};
}
