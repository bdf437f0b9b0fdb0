// The page's one state object, which every view renders from, and the small
// helpers every module uses. Canvas units: origin top-left, y down.
export const $ = (id) => document.getElementById(id);

export const state = {
  info: null,  // GET /api/info: mode, size, canvas, scale, offset, end, input, error
  doc: null,  // the recipe shown and edited (the saved one, or a newer one on its way)
  types: null,  // GET /api/ops: the op types, their parameters and tools
  tools: [],  // the tool table (tools.js), built from types
  version: null,  // the recipe's version as last saved or read
  tool: null,  // the active tool's name (the first tool at load)
  selected: null,  // the op whose editors and handles are shown
  solo: null,  // the op shown alone: the page's view only (hide is saved)
  undoStack: [],
  redoStack: [],
  t: 0,  // the time shown, in seconds
  playing: false,
  frames: 0,  // frames drawn on the sheet
  gesture: null,  // the pointer's drag under way
  liveSeq: 0,  // live mode: the sequence number of the frame shown
  fields: 0,  // counts the editors shown: a field removed with a value typed in is dropped
};

export const isLive = () => !!state.info && state.info.mode === "live";
export const round1 = (v) => Math.round(v * 10) / 10;
export const round3 = (v) => Math.round(v * 1000) / 1000;
// The canvas's smaller side, in canvas units.
export const side = () => Math.min(state.info.canvas[0], state.info.canvas[1]);
export const clone = (v) => JSON.parse(JSON.stringify(v));

export function setStatus(text) { $("status").textContent = text; }
export function showError(message) {
  const e = $("error");
  e.textContent = message || "";
  e.style.display = message ? "block" : "none";
}
export function isTrack(v) { return v !== null && typeof v === "object" && !Array.isArray(v) && "keys" in v; }
export function isSignal(v) { return v !== null && typeof v === "object" && !Array.isArray(v) && "signal" in v; }
