// The recipe: read (GET /api/recipe, following FILE when another program saves
// it), saved (PUT), undone and redone. Edits run one after another, each on the
// recipe the one before left. These only change the store: the views follow it.
import * as api from "./api.js";
import { get, update } from "./store.js";
import { clone } from "./values.js";

// The timeline's end: the recipe's, the input's, at least 1 s.
const durationOf = (info) => Math.max(info.end || 0, info.input.duration || 0, 1);
// The store's fields for a new /api/info answer (the time shown kept within it).
export function withInfo(s, info) {
  const duration = durationOf(info);
  return {info, duration, t: Math.min(s.t, duration)};
}
export async function loadInfo() {
  const info = await api.info();
  update((s) => withInfo(s, info));
}
// The file's recipe as of ``now`` (an /api/info answer). Dropped when a save
// of the page's own lands meanwhile: that answer is newer than this read.
// While FILE on disk is broken (409), the last good recipe, and the error shown.
export async function loadRecipe(now) {
  const seen = get().version;
  const r = await api.recipe(), answer = await r.json();
  const next = r.status === 409 ? answer.last_good : answer;
  if (r.status === 409) update(() => ({error: answer.error}));
  if (get().version !== seen || get().saving) return false;
  update((s) => {
    const changes = {...withInfo(s, now), version: now.version};
    if (s.doc && JSON.stringify(next) === JSON.stringify(s.doc)) return changes;  // the same: leave the editors be
    const within = (i) => (i !== null && i >= next.ops.length ? null : i);
    return {...changes, doc: next, selected: within(s.selected), solo: within(s.solo)};
  });
  return true;
}
// An edit recorded for undo: the recipe before it on the undo stack, redo emptied.
const recorded = (s, before) => ({undo: [...s.undo, before], redo: []});
// Save ``next`` (PUT): on success it is the recipe (the stacks as ``stacks``
// leaves them), else the error is shown and nothing changes.
export async function commit(next, stacks = recorded) {
  const before = JSON.stringify(get().doc);
  update((s) => ({saving: s.saving + 1}));
  let r, answer;
  try {
    r = await api.putRecipe(next);
    answer = await r.json();
  } catch (e) {
    update((s) => ({saving: s.saving - 1, preview: null}));
    throw e;
  }
  if (!r.ok) {  // refused: the editors show the recipe again
    update((s) => ({saving: s.saving - 1, preview: null, error: answer.error, refusals: s.refusals + 1}));
    return false;
  }
  update((s) => {
    const info = {...s.info, ...answer};
    return {...withInfo(s, info), ...stacks(s, before), saving: s.saving - 1, preview: null,
      doc: next, version: answer.version, error: info.error};
  });
  return true;
}
// Undo and redo move recipes between the two stacks; a refused save moves nothing.
async function travel(from, to) {
  const stack = get()[from];
  if (!stack.length) return;
  const target = stack.at(-1);
  await commit(JSON.parse(target), (s, before) => ({[from]: s[from].slice(0, -1), [to]: [...s[to], before]}));
}
let edits = Promise.resolve();
// Run ``task`` once the edits before it are done (an edit made while a save is
// on its way waits for its answer).
export function serial(task) {
  const run = edits.then(task, task);
  edits = run.catch(() => {});
  return run;
}
export const undo = () => serial(() => travel("undo", "redo"));
export const redo = () => serial(() => travel("redo", "undo"));
// Save the recipe as ``change`` leaves a copy of it.
export function edited(change) {
  return serial(() => {
    const next = clone(get().doc);
    change(next);
    return commit(next);
  });
}
// Follow FILE (saved by another program) and the server's error, every 500 ms;
// ``more``: what else follows the server (live mode's counters).
export async function poll(more) {
  try {
    const now = await api.info();
    if (now.version !== get().version && !get().saving) await loadRecipe(now);  // FILE changed on disk
    const {info} = get();
    if (now.error !== (info && info.error)) update((s) => ({info: {...s.info, error: now.error}, error: now.error}));
    await more();
  } catch (e) { update(() => ({status: "offline"})); }
  setTimeout(() => poll(more), 500);
}
