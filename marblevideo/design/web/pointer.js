// The pointer on the sheet: a drag with the active tool adds the op it makes
// (a draft follows the hand, the exact frame when it stops, saved when it lets
// go); a drag from a handle of the selected op moves that point. A "path" tool
// draws along the pointer's path. Input that comes before the page has its
// recipe (a click as the page appears) is kept, as fractions of the sheet, and
// replayed once it has; the sheet shows a progress cursor meanwhile.
import { color, inks } from "./palette.js";
import { showOps } from "./oplist.js";
import { commit, serial } from "./recipe.js";
import {
  overlay, drawHandles, drawPath, eventPixel, handleAt, setHandle, show, toCanvas,
} from "./sheet.js";
import { state, isLive, side, clone } from "./state.js";
import { gestureEnv, makeOp, pathPoints, settingValue } from "./tools.js";

let early = [], earlyDown = false, stillTimer = null, drawn = [];
const toolNamed = (name) => state.tools.find((t) => t.name === name);

// The op the tool ``name`` makes for a gesture from canvas point a to b.
export function toolOp(name, a, b) {
  const tool = toolNamed(name), {scale} = state.info, s = side();
  const env = gestureEnv(a, b, s, scale, {color: color(), inks: inks(), seed: Math.floor(Math.random() * 1e9)});
  env.setting = Object.fromEntries(tool.settings.map((x) => [x.name, settingValue(tool.type, x, env)]));
  if (tool.gesture === "path") env.path = pathPoints(drawn, a, b, s, scale);
  return makeOp(tool, env);
}
// The number a drag sets, shown beside the hand while it moves.
function dragLabel(g, op) {
  const name = toolNamed(g.tool).label;
  return name ? `${name} ${op[name]}` : "";
}
function gestureDoc(g = state.gesture) {
  const next = clone(state.doc);
  if (g.handle) setHandle(next.ops[g.op], g.handle, g.b);
  else next.ops.push(toolOp(g.tool, g.a, g.b));
  return next;
}
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
    early.push({handler, type: ev.type, button: ev.button, pointerId: ev.pointerId,
      fx: (ev.clientX - r.left) / r.width, fy: (ev.clientY - r.top) / r.height});
  });
}
export function replayEarly() {
  const r = overlay.getBoundingClientRect();
  for (const e of early.splice(0)) {
    e.handler({type: e.type, button: e.button, pointerId: e.pointerId,
      clientX: r.left + e.fx * r.width, clientY: r.top + e.fy * r.height});
  }
}
function down(ev) {
  if (!state.doc || ev.button !== 0) return;
  capture(ev.pointerId);
  const px = eventPixel(ev), a = toCanvas(px);
  // the op and tool as the hand went down
  state.gesture = {a, b: a, handle: handleAt(px), op: state.selected, tool: state.tool, draft: null};
}
function moved(ev) {
  const g = state.gesture;
  if (!g) return;
  g.b = toCanvas(eventPixel(ev));
  g.draft = gestureDoc();
  const label = g.label = g.handle ? "" : dragLabel(g, g.draft.ops.at(-1));
  if (isLive()) { drawHandles([g.a, g.b], label); return; }  // the live frame shows what is saved
  show({draft: true, doc: g.draft});
  drawHandles(g.handle ? null : [g.a, g.b], label);
  clearTimeout(stillTimer);  // the hand stopped: the exact render of the draft
  stillTimer = setTimeout(() => { if (state.gesture) show({doc: state.gesture.draft}); }, 250);
}
async function up(ev) {
  if (!state.gesture) return;
  clearTimeout(stillTimer);
  if (ev.type === "pointerup") state.gesture.b = toCanvas(eventPixel(ev));
  const g = state.gesture;
  state.gesture = null;
  if (ev.type !== "pointerup" || (g.handle && g.a[0] === g.b[0] && g.a[1] === g.b[1])) { show(); drawHandles(); return; }
  // a draft of the result at once (a heavy design's exact frame takes longer), then the exact
  if (!isLive()) show({draft: true, doc: gestureDoc(g)});
  await serial(async () => {
    const next = gestureDoc(g);
    if (await commit(next) && !g.handle) state.selected = next.ops.length - 1;
  });
  showOps();
  drawHandles();
}
const pathGesture = () => {
  const g = state.gesture;
  return g && !g.handle && toolNamed(g.tool).gesture === "path";
};
export function initPointer() {
  onPointer("pointerdown", down);
  onPointer("pointermove", moved);
  onPointer("pointerup", up);
  onPointer("pointercancel", up);
  // a path tool's path: from where the hand went down (before the gesture starts)
  overlay.addEventListener("pointerdown", (ev) => {
    drawn = state.doc && ev.button === 0 ? [toCanvas(eventPixel(ev))] : [];
  }, {capture: true});
  for (const type of ["pointermove", "pointerup"]) {
    overlay.addEventListener(type, (ev) => {  // before the gesture's own listener
      if (pathGesture()) drawn.push(toCanvas(eventPixel(ev)));
    }, {capture: true});
  }
  overlay.addEventListener("pointermove", () => {  // after it: the path drawn, not a line
    if (!pathGesture()) return;
    drawHandles();
    drawPath(drawn);
  });
}
