// The recipe: read (GET /api/recipe, following FILE when another program saves
// it), saved (PUT), undone and redone. Edits run one after another, each on the
// recipe the one before left.
import * as api from "./api.js";
import { showOps } from "./oplist.js";
import { render, resize, show } from "./sheet.js";
import { $, state, isLive, clone, setStatus, showError } from "./state.js";
import { liveStats, setDuration } from "./timeline.js";

export async function loadInfo() {
  const info = state.info = await api.info();
  resize(info.size);
  $("file").textContent = info.file;
  $("export-recipe").download = info.file.split("/").pop();
  $("export-svg").style.display = info.input.kind === "blank" ? "" : "none";
  $("live-controls").hidden = !isLive();
  document.body.dataset.mode = info.mode || "design";
  setDuration();
}
// The file's recipe as of ``now`` (an /api/info answer). Dropped when a save
// of the page's own lands meanwhile: that answer is newer than this read.
// While FILE on disk is broken (409), the last good recipe, and the error shown.
export async function loadRecipe(now) {
  const seen = state.version;
  const r = await api.recipe(), answer = await r.json();
  const next = r.status === 409 ? answer.last_good : answer;
  if (r.status === 409) showError(answer.error);
  if (state.version !== seen || render.committing) return false;
  state.info = now;
  state.version = now.version;
  if (state.doc && JSON.stringify(next) === JSON.stringify(state.doc)) return true;  // the same: leave the editors be
  state.doc = next;
  if (state.selected !== null && state.selected >= next.ops.length) state.selected = null;
  if (state.solo !== null && state.solo >= next.ops.length) state.solo = null;
  showOps();
  return true;
}
// Save ``next`` (PUT): on success it is the recipe (and undoable), else the
// error is shown and nothing changes.
export async function commit(next, record = true) {
  const before = JSON.stringify(state.doc);
  render.committing += 1;
  let r, answer;
  try {
    r = await api.putRecipe(next);
    answer = await r.json();
  } finally { render.committing -= 1; }
  if (!r.ok) {
    showError(answer.error);
    showOps();
    show();
    return false;
  }
  if (record) { state.undoStack.push(before); state.redoStack = []; }
  state.doc = next;
  state.info = Object.assign(state.info, answer);
  state.version = answer.version;
  showError(state.info.error);
  setDuration();
  showOps();
  show();
  return true;
}
// Undo and redo move recipes between the two stacks; a refused save moves nothing.
async function travel(from, to) {
  if (!from.length) return;
  const target = from.pop(), current = JSON.stringify(state.doc);
  to.push(current);
  if (!await commit(JSON.parse(target), false)) { to.pop(); from.push(target); showOps(); }
}
let edits = Promise.resolve();
// Run ``task`` once the edits before it are done (an edit made while a save is
// on its way waits for its answer).
export function serial(task) {
  const run = edits.then(task, task);
  edits = run.catch(() => {});
  return run;
}
export const undo = () => serial(() => travel(state.undoStack, state.redoStack));
export const redo = () => serial(() => travel(state.redoStack, state.undoStack));
// Save the recipe as ``change`` leaves a copy of it.
export function edited(change) {
  return serial(() => {
    const next = clone(state.doc);
    change(next);
    return commit(next);
  });
}
export async function poll() {
  try {
    const now = await api.info();
    if (now.version !== state.version && !render.committing && await loadRecipe(now)) {  // FILE changed on disk
      setDuration();
      show();
    }
    const info = state.info;
    if (now.error !== (info && info.error)) { info.error = now.error; showError(now.error); }
    if (isLive()) await liveStats();
  } catch (e) { setStatus("offline"); }
  setTimeout(poll, 500);
}
