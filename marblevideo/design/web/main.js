// The designer's page (marblevideo.design): everything goes through its HTTP
// API. In "live" mode (/api/info's mode: marblevideo live --preview) the sheet
// shows the live marbled frames, edits are saved to the live recipe, and the
// clock is the live session's. The op types, their editors and the tools all
// come from GET /api/ops: this page names none. This module wires the page:
// the store's views are subscribed here, each with what it shows of the store.
import * as api from "./api.js";
import { actionsOf, initActions, showActions } from "./actions.js";
import { valueAt } from "./ease.js";
import { gesture, timedTool, toolOp } from "./gestures.js";
import { groundOf, initGround, showGround } from "./ground.js";
import { restoreHistory } from "./history.js";
import { exportsOf, fileOf, messagesOf, showExports, showFile, showMessages } from "./header.js";
import { rangeOf, valueNow } from "./numbers.js";
import { opListOf, showOps } from "./oplist.js";
import { overlayOf, pointsOf, showOverlay } from "./overlay.js";
import { initPalette, paletteOf, showPalette } from "./palette.js";
import { paramsOf, showParams } from "./params.js";
import { initPointer, replayEarly } from "./pointer.js";
import { initMotion, motionFieldsOf, motionLevelOf, showMotionFields, showMotionLevel } from "./motion.js";
import { loadInfo, loadRecipe, poll } from "./recipe.js";
import { initRecord, newestInput } from "./record.js";
import { isRendering, resize, screenOf, sheetOf, showSheet, whenIdle } from "./sheet.js";
import { get, isLive, subscribe, update } from "./store.js";
import { clockOf, initTimeline, liveStats, playOf, resume, setTime, showClock, showPlay } from "./timeline.js";
import { buildToolbar } from "./toolbar.js";
import { buildTools } from "./tools.js";
import { initSize, initView, panBy, resetView, toCanvas, toPixel, zoomAt } from "./view.js";
import { prefetchLayers, warmLive, warpState } from "./warping.js";
import { shownPixels, warpShown } from "./sheetgl.js";

// The views that need the recipe and /api/info, in the order they first run
// (the canvas sized before the sheet renders).
const VIEWS = [
  [screenOf, resize],
  [fileOf, showFile],
  [exportsOf, showExports],
  [clockOf, showClock],
  [playOf, showPlay],
  [actionsOf, showActions],
  [groundOf, showGround],
  [opListOf, showOps],
  [paramsOf, showParams],
  [overlayOf, showOverlay],
  [sheetOf, showSheet],
  [motionFieldsOf, showMotionFields],
  [motionLevelOf, showMotionLevel],
  [(s) => [s.gesture === null], resume],  // the clock goes on after a gesture
  [(s) => [s.selected, s.doc, s.preview, s.screen, s.view, s.playing, s.solo], prefetchLayers],
  [(s) => [isLive(s) && s.tool, s.screen, s.view], warmTool],
];
// Live mode: the chosen tool's programs compiled before its first gesture (an op of
// it drawn across the middle of the canvas stands for what the gesture will make).
function warmTool(s) {
  if (!isLive(s) || !s.screen || !s.doc) return;
  const [cw, ch] = s.info.canvas, a = [0.4 * cw, 0.5 * ch], b = [0.6 * cw, 0.5 * ch];
  try { warmLive(s, toolOp(s.tool, a, b, [a, b], timedTool(s.tool, s) ? [s.t, s.t + 0.1] : null)); }
  catch (e) { /* a tool whose op needs more: its first gesture compiles */ }
}

async function start() {
  const types = await api.ops(), tools = buildTools(types);
  update((s) => ({types, tools, tool: s.tool || tools[0].name}));
  buildToolbar(tools, types);
  await loadInfo();
  await loadRecipe(get().info);
  restoreHistory();
  const {info} = get();
  if (isLive()) await liveStats();
  else setTime(info.input.kind === "video" ? 0 : Math.min(info.end, get().duration));
  update(() => ({error: info.error}));
  await initMotion();
  for (const [select, view] of VIEWS) subscribe(select, view);
  document.body.dataset.ready = "1";
  replayEarly();
  poll(async () => { if (isLive()) await liveStats(); });
}

subscribe(messagesOf, showMessages);
subscribe(paletteOf, showPalette);
initActions();
initPalette();
initGround();
initPointer();
initTimeline();
initSize();
initView();
initRecord();
whenIdle(resume);
// For scripts and tests: the page's state, its store and its evaluations.
window.designer = {
  get state() { return get(); },
  store: {get, update, subscribe},
  gesture, valueNow, valueAt, rangeOf, toolOp,
  handles: (i) => pointsOf(i),  // op i's handles: [name, point]
  setTool: (name) => update(() => ({tool: name})),
  warp: warpState,  // whether the page warps during gestures (warp.js loaded, WebGL2), layers held
  sheetPixels: shownPixels,  // the pixels the sheet shows now (ImageData), whichever canvas shows them
  glShown: warpShown,  // whether the warp's WebGL canvas shows the sheet now (a gesture's frames)
  rendering: isRendering,  // whether a server frame is on its way (benchmarks settle on it)
  newestInput,  // the newest pointer (or slider) input's number and time (record.js)
  zoomAt, panBy, resetView,  // the view (zoom about a device pixel, pan by device pixels)
  toCanvas, toPixel,  // the sheet's device pixels <-> canvas points, through the view
};
start();
