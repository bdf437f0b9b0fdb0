// The pointer's gestures on the sheet, each a small state machine (as tldraw's
// tools): idle -> pointing (pressed, not moved yet) -> dragging -> idle. Each
// state answers down, move, up and cancel with the state that follows. What a
// press starts is a gesture kind, chosen by ``kindAt``: in the move mode (the
// Move button, M) or with Alt held, a press on a handle of the selected op moves
// that point; otherwise the active tool adds the op it makes wherever the press
// lands (a "path" tool records the path drawn), so a tool never moves an op. While dragging, the sheet
// shows a draft of the recipe the gesture would leave (the exact render once
// the hand stops for 250 ms); letting go saves it. The store's ``gesture`` is
// what the overlay shows of the gesture under way.
import { select } from "./edits.js";
import { handleAt, setHandle } from "./overlay.js";
import { inks } from "./palette.js";
import { commit, serial } from "./recipe.js";
import { get, update, isLive, side } from "./store.js";
import { gestureEnv, makeOp, pathPoints, settingValue } from "./tools.js";
import { clone } from "./values.js";

const toolNamed = (name) => get().tools.find((t) => t.name === name);

// The op the tool ``name`` makes for a gesture from canvas point a to b
// (``drawn``: the path a "path" tool's gesture drew).
export function toolOp(name, a, b, drawn = []) {
  const s = get(), tool = toolNamed(name), {scale} = s.info, sd = side(s);
  const env = gestureEnv(a, b, sd, scale, {color: s.color, inks: inks(s), seed: Math.floor(Math.random() * 1e9)});
  const typed = (x) => s.settings[`${tool.type}-${x.name}`];
  env.setting = Object.fromEntries(tool.settings.map((x) => [x.name, settingValue(x, env, typed(x))]));
  if (tool.gesture === "path") env.path = pathPoints(drawn, a, b, sd, scale);
  return makeOp(tool, env);
}

// The gesture kinds: how each starts, what recipe it leaves, what the overlay
// shows of it, whether letting go saves it, and whether the op it made is then selected.
const KINDS = {
  handle: {  // a handle of the selected op: that point follows the pointer
    start: (s, px) => ({op: s.selected, handle: handleAt(px, s)}),
    doc(g, doc) { const next = clone(doc); setHandle(next.ops[g.op], g.handle, g.b); return next; },
    shown: (g) => ({a: g.a, b: g.b, label: "", line: isLive(), path: null}),
    saves: (g) => g.a[0] !== g.b[0] || g.a[1] !== g.b[1],  // a press that moved nothing saves nothing
    selects: false,
  },
  tool: {  // the active tool: the op it makes for the gesture
    start: (s, px, at) => ({tool: s.tool, path: toolNamed(s.tool).gesture === "path" ? [at] : null}),
    doc(g, doc) { const next = clone(doc); next.ops.push(toolOp(g.tool, g.a, g.b, g.path || [])); return next; },
    shown(g, draft) {
      const name = toolNamed(g.tool).label, op = draft.ops.at(-1);
      return {a: g.a, b: g.b, label: name ? `${name} ${op[name]}` : "", line: true, path: g.path};
    },
    saves: () => true,  // a click adds the op as well
    selects: true,
  },
};
// The kind of gesture a press at frame pixel px starts (``alt``: Alt held).
const kindAt = (s, px, alt) => ((s.moving || alt) && handleAt(px, s) !== null ? "handle" : "tool");

let stillTimer = null;
const idle = {
  name: "idle",
  down(at, px, alt = false) {
    const s = get(), kind = kindAt(s, px, alt);
    const g = {kind, a: at, b: at, ...KINDS[kind].start(s, px, at)};
    update(() => ({gesture: {a: at, b: at, label: "", line: false, path: null}}));
    return pointing(g);
  },
  move: () => idle, up: () => idle, cancel: () => idle,
};
function pointing(g) {
  const self = {name: `pointing ${g.kind}`, down: () => self, move: (at) => dragging(g).move(at),
    up: (at) => done(g, at), cancel: () => cancelled()};
  return self;
}
function dragging(g) {
  const self = {
    name: `dragging ${g.kind}`,
    move(at) {
      const kind = KINDS[g.kind];
      g.b = at;
      if (g.path) g.path.push(at);
      const draft = kind.doc(g, get().doc), live = isLive();  // the live frame shows what is saved
      update(() => ({gesture: kind.shown(g, draft), ...(live ? {} : {preview: {doc: draft, draft: true}})}));
      clearTimeout(stillTimer);  // the hand stopped: the exact render of the draft
      if (!live) stillTimer = setTimeout(() => { if (current === self) update(() => ({preview: {doc: draft, draft: false}})); }, 250);
      return self;
    },
    down: () => self, up: (at) => done(g, at), cancel: () => cancelled(),
  };
  return self;
}
function cancelled() {
  clearTimeout(stillTimer);
  update(() => ({gesture: null, preview: null}));
  return idle;
}
// Let go at ``at``: a draft of the result at once (a heavy design's exact frame
// takes longer), then saved, on the recipe the edits before it leave.
function done(g, at) {
  const kind = KINDS[g.kind];
  g.b = at;
  if (g.path) g.path.push(at);
  if (!kind.saves(g)) return cancelled();
  clearTimeout(stillTimer);
  const draft = isLive() ? null : {doc: kind.doc(g, get().doc), draft: true};
  update(() => ({gesture: null, preview: draft}));
  serial(async () => {
    const next = kind.doc(g, get().doc);
    if (await commit(next) && kind.selects) select(next.ops.length - 1);
  });
  return idle;
}

let current = idle;
// The pointer's events, at canvas point ``at`` (and frame pixel px for a press).
export const gesture = {
  down(at, px, alt) { current = current.down(at, px, alt); },
  move(at) { current = current.move(at); },
  up(at) { current = current.up(at); },
  cancel() { current = current.cancel(); },
  get state() { return current.name; },
};
