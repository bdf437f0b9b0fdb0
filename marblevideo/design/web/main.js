// The designer's page (marblevideo.design): everything goes through its HTTP
// API. In "live" mode (/api/info's mode: marblevideo live --preview) the sheet
// shows the live marbled frames, edits are saved to the live recipe, and the
// clock is the live session's. The op types, their editors and the tools all
// come from GET /api/ops: this page names none.
import * as api from "./api.js";
import { valueAt } from "./ease.js";
import { remove } from "./oplist.js";
import { initPalette } from "./palette.js";
import { initPointer, replayEarly, toolOp } from "./pointer.js";
import { rangeOf, valueNow } from "./params.js";
import { loadInfo, loadRecipe, poll, redo, undo } from "./recipe.js";
import { fitSheet, show } from "./sheet.js";
import { $, state, isLive, showError } from "./state.js";
import { initTimeline, liveStats, setTime } from "./timeline.js";
import { buildTools, settingControls } from "./tools.js";

const GESTURE_HELP = {click: "click (drag to size)", line: "drag a line", centre: "drag from the centre", path: "draw a path"};

function setTool(name) {
  state.tool = name;
  for (const b of $("tools").children) b.classList.toggle("on", b.dataset.tool === name);
}
function showTools() {
  state.tools = buildTools(state.types);
  for (const tool of state.tools) {
    const b = document.createElement("button");
    b.textContent = tool.name; b.dataset.tool = tool.name; b.id = `tool-${tool.name}`;
    b.title = `${tool.name}: ${GESTURE_HELP[tool.gesture]}`;
    b.addEventListener("click", () => setTool(tool.name));
    $("tools").appendChild(b);
  }
  settingControls(state.types);
  setTool(state.tool || state.tools[0].name);
}
function keys(ev) {
  if (ev.target.tagName === "INPUT" || ev.target.tagName === "SELECT") return;
  const mod = ev.ctrlKey || ev.metaKey;
  if (mod && ev.key.toLowerCase() === "z") { ev.preventDefault(); (ev.shiftKey ? redo : undo)(); }
  else if (mod && ev.key.toLowerCase() === "y") { ev.preventDefault(); redo(); }
  else if ((ev.key === "Delete" || ev.key === "Backspace") && state.selected !== null) remove(state.selected);
}
async function start() {
  state.types = await api.ops();
  showTools();
  await loadInfo();
  await loadRecipe(state.info);
  const {info} = state;
  if (isLive()) {
    $("export-png").download = "frame.jpg";
    await liveStats();
  } else setTime(info.input.kind === "video" ? 0 : Math.min(info.end, Number($("time").max)), false);
  showError(info.error);
  show();
  document.body.dataset.ready = "1";
  replayEarly();
  poll();
}

initPalette();
initPointer();
initTimeline();
$("undo").addEventListener("click", undo);
$("redo").addEventListener("click", redo);
document.addEventListener("keydown", keys);
window.addEventListener("resize", () => { if (state.info) fitSheet(); });
// For scripts and tests: the page's state and its evaluations.
window.designer = {state, valueNow, valueAt, rangeOf, toolOp, setTool};
start();
