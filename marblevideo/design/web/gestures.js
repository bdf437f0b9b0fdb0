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
//
// A timed tool (a "path" tool whose op takes ``times``: stroke, comb-stroke)
// draws in time (stylus.js): the stroke grows as the pointer moves, its times
// the timeline's time at the press plus the seconds since it, and the sheet
// follows the newest point's time (after release it stays at the stroke's last
// time, the finished stroke). In live mode the growing stroke goes to the live
// session (livepreview.js), its times on the live clock (none while it is paused).
import { select } from "./edits.js";
import { clockAtPress, clearPreview, sendPreview } from "./livepreview.js";
import { handleAt, setHandle } from "./overlay.js";
import { liveGesture } from "./sheet.js";
import { inks } from "./palette.js";
import { commit, serial } from "./recipe.js";
import { get, update, isLive, side } from "./store.js";
import { addPoint, drawn, lastTime, startPath, timesFrom } from "./stylus.js";
import { drawsInTime, gestureEnv, makeOp, pathPoints, settingValue } from "./tools.js";
import { clone } from "./values.js";

const toolNamed = (name) => get().tools.find((t) => t.name === name);
// Whether tool ``name`` draws in time: a path tool whose op takes ``times``.
export function timedTool(name, s = get()) {
  const tool = s.tools.find((t) => t.name === name);
  return !!tool && drawsInTime(tool, s.types);
}

// The op the tool ``name`` makes for a gesture from canvas point a to b
// (``drawn``: the path a "path" tool's gesture drew; ``times``: its points'
// times, when it was drawn in time: the path is then kept as drawn).
export function toolOp(name, a, b, drawn = [], times = null) {
  const s = get(), tool = toolNamed(name), {scale} = s.info, sd = side(s);
  const env = gestureEnv(a, b, sd, scale, {color: s.color, inks: inks(s), seed: Math.floor(Math.random() * 1e9)});
  const typed = (x) => s.settings[`${tool.type}-${x.name}`];
  env.setting = Object.fromEntries(tool.settings.map((x) => [x.name, settingValue(x, env, typed(x))]));
  const timed = times !== null && moved(drawn);
  if (tool.gesture === "path") env.path = timed ? drawn : pathPoints(drawn, a, b, sd, scale);
  const op = makeOp(tool, env);
  if (timed) op.times = times;
  return op;
}
// Whether a path goes anywhere (its canvas points are not all one).
const moved = (pts) => pts.some((p) => p[0] !== pts[0][0] || p[1] !== pts[0][1]);

// A timed gesture's times, once its clock is known (null: untimed, a click or a paused live clock).
const timesOf = (g) => (g.stylus && g.t0 !== null && drawn(g.stylus) ? timesFrom(g.stylus, g.t0) : null);
// (a copy: the path grows after a draft is made, and a draft's points and times must stay in step)
const pathOf = (g) => (g.stylus ? g.stylus.points.slice() : g.path && g.path.slice());  // null: not a path tool

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
    start(s, px, at, ev) {
      if (timedTool(s.tool, s)) return timedStart(s, at, ev);
      return {tool: s.tool, path: toolNamed(s.tool).gesture === "path" ? [at] : null};
    },
    doc(g, doc) { const next = clone(doc); next.ops.push(toolOp(g.tool, g.a, g.b, pathOf(g) || [], timesOf(g))); return next; },
    shown(g, draft) {
      const name = toolNamed(g.tool).label, op = draft.ops.at(-1);
      return {a: g.a, b: g.b, label: name ? `${name} ${op[name]}` : "", line: true, path: pathOf(g)};
    },
    saves: () => true,  // a click adds the op as well
    selects: true,
  },
};
// A timed tool's press: its path and its clock (the timeline's time; in live
// mode the live clock's, asked of the session: see ``anchored``).
const timedStart = (s, at, ev) => ({tool: s.tool, stylus: startPath(at, ev.dev, ev.stamp), t0: s.t,
  before: {t: s.t, duration: s.duration}});
// Gesture ``g`` in live mode: its clock unknown (``anchor``) until the session answers.
function anchored(g, ev) {
  if (!g.stylus || !isLive()) return g;
  g.t0 = null;
  g.anchor = clockAtPress(ev.stamp).then((t0) => { g.t0 = t0; });
  return g;
}
// The kind of gesture a press at frame pixel px starts (``alt``: Alt held).
const kindAt = (s, px, alt) => ((s.moving || alt) && handleAt(px, s) !== null ? "handle" : "tool");

let stillTimer = null;
const idle = {
  name: "idle",
  down(at, px, ev) {
    const s = get(), kind = kindAt(s, px, ev.alt);
    const g = anchored({kind, a: at, b: at, ...KINDS[kind].start(s, px, at, ev)}, ev);
    update(() => ({gesture: {a: at, b: at, label: "", line: false, path: null}}));
    return pointing(g);
  },
  move: () => idle, up: () => idle, cancel: () => idle,
};
function pointing(g) {
  const self = {name: `pointing ${g.kind}`, down: () => self, move: (at, ev) => dragging(g).move(at, ev),
    up: (at, ev) => done(g, at, ev), cancel: () => cancelled(g)};
  return self;
}
// The pointer at ``at``: whether the gesture changed (a timed path takes a
// point only where the pointer has moved a device pixel).
function follow(g, at, ev) {
  g.b = at;
  if (g.stylus && ev.samples && ev.samples.length) {  // every move the browser coalesced, in order
    return ev.samples.map(([p, e]) => addPoint(g.stylus, p, e.dev, e.stamp)).some(Boolean);
  }
  if (g.stylus) return addPoint(g.stylus, at, ev.dev, ev.stamp);
  if (g.path) g.path.push(at);
  return true;
}
// What the store takes of a timed gesture's draft: the time of its newest point
// (the sheet shows the stroke as far as drawn), the timeline stretched to it.
function timedView(g) {
  if (!g.stylus || g.t0 === null || isLive()) return {};
  const t = lastTime(g.stylus, g.t0);
  return {t, duration: Math.max(g.before.duration, t)};
}
function dragging(g) {
  const self = {
    name: `dragging ${g.kind}`,
    move(at, ev) {
      const kind = KINDS[g.kind];
      if (!follow(g, at, ev)) return self;
      const draft = kind.doc(g, get().doc), live = isLive();
      if (live) sendPreview(() => kind.doc(g, get().doc), get().version, g.anchor);  // the live frames show the gesture
      if (live && g.t0 !== null) liveGesture(draft);  // the newest live frame warped to it meanwhile
      update(() => ({gesture: kind.shown(g, draft), ...timedView(g), ...(live ? {} : {preview: {doc: draft, draft: true}})}));
      clearTimeout(stillTimer);  // the hand stopped: the exact render of the draft
      if (!live) stillTimer = setTimeout(() => { if (current === self) update(() => ({preview: {doc: draft, draft: false}})); }, 250);
      return self;
    },
    down: () => self, up: (at, ev) => done(g, at, ev), cancel: () => cancelled(g),
  };
  return self;
}
function cancelled(g) {
  clearTimeout(stillTimer);
  liveGesture(null);
  if (isLive()) clearPreview(get().version);
  update(() => ({gesture: null, preview: null, ...(g.stylus && !isLive() ? g.before : {})}));
  return idle;
}
// Let go at ``at``: a draft of the result at once (a heavy design's exact frame
// takes longer), then saved, on the recipe the edits before it leave. A timed
// stroke leaves the sheet at its last time: the finished stroke.
function done(g, at, ev) {
  const kind = KINDS[g.kind];
  follow(g, at, ev);
  if (!kind.saves(g)) return cancelled(g);
  clearTimeout(stillTimer);
  liveGesture(null);
  const draft = isLive() ? null : {doc: kind.doc(g, get().doc), draft: true};
  update(() => ({gesture: null, preview: draft, ...timedView(g)}));
  serial(async () => {
    if (g.anchor) await g.anchor;  // live mode: the stroke's times wait for the live clock
    const next = kind.doc(g, get().doc);
    if (isLive()) clearPreview(null);  // newer sends are dropped; the save replaces the preview
    if (await commit(next) && kind.selects) select(next.ops.length - 1);
  });
  return idle;
}

let current = idle;
// The pointer's events, at canvas point ``at`` (and frame pixel px for a
// press); ``ev``: {alt (Alt held), dev (the device pixel), stamp (the event's
// timeStamp, ms), samples (a move's coalesced moves: [at, {dev, stamp}], or none)}.
const NO_EVENT = {alt: false, dev: [0, 0], stamp: 0};
export const gesture = {
  down(at, px, ev = NO_EVENT) { current = current.down(at, px, {...NO_EVENT, ...ev}); },
  move(at, ev = NO_EVENT) { current = current.move(at, {...NO_EVENT, ...ev}); },
  up(at, ev = NO_EVENT) { current = current.up(at, {...NO_EVENT, ...ev}); },
  cancel() { current = current.cancel(); },
  get state() { return current.name; },
};
