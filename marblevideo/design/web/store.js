// The page's one store: the state every view renders from. ``update(fn)``
// gives fn the state and takes back the fields that change (a new state object
// is made; values are replaced, never changed in place, so views can compare
// them by identity); ``subscribe(select, view)`` calls view(state) once now and
// again whenever one of the values select(state) lists has changed. Mutators
// only update the store; views (subscribed in main.js) only read it.

let state = {
  info: null,  // GET /api/info: mode, size, canvas, scale, offset, end, input, error
  doc: null,  // the recipe shown and edited (the saved one, or a newer one on its way)
  preview: null,  // {doc, draft}: a recipe not saved shown on the sheet (a gesture, a slider)
  types: null,  // GET /api/ops: the op types, their parameters and tools
  tools: [],  // the tool table (tools.js), built from types
  version: null,  // the recipe's version as last saved or read
  saving: 0,  // saves on their way: renders wait for their answer
  tool: null,  // the active tool's name (the first tool at load)
  moving: false,  // the move mode: a press on the selected op's handle moves it (else tools draw)
  settings: {},  // the tools' settings typed in, by "TYPE-NAME" (empty: from the canvas)
  color: "#1d3557",  // the ink a new op takes
  palette: "classic",  // the colours a layout's drops take in turn (after color)
  selected: null,  // the op whose editors and handles are shown
  solo: null,  // the op shown alone: the page's view only (hide is saved)
  undo: [],  // the recipes before each edit (JSON), newest last
  redo: [],
  t: 0,  // the time shown, in seconds
  duration: 1,  // the timeline's end, in seconds
  playing: false,
  loop: true,  // play starts again at the end
  gesture: null,  // the pointer's gesture as the overlay shows it: {kind, a, b, label, line, path}
  error: "",  // the error shown over the sheet
  refusals: 0,  // saves refused: the editors show the recipe again after each
  status: "",  // the footer's line
  live: null,  // live mode: the session's counters and switches (GET /stats)
  motion: null,  // the motion of the last frame (GET /api/motion; tracked over a live source or a video only)
  showMotion: false,  // over a live source or a video: the motion's regions and strokes drawn over the sheet
  view: null,  // the window of the canvas the sheet shows, [x, y, w, h] canvas units (null: the frame's)
  screen: null,  // the sheet's size in device pixels [w, h] (its CSS size x devicePixelRatio)
};
const views = [];

export const get = () => state;

export function update(fn) {
  const changes = fn(state);
  if (!changes) return;
  state = {...state, ...changes};
  for (const v of views) notify(v);
}

function changed(a, b) {
  return a.length !== b.length || a.some((x, k) => !Object.is(x, b[k]));
}
function notify(v) {
  const now = v.select(state);
  if (v.seen !== null && !changed(v.seen, now)) return;
  v.seen = now;  // before the view runs: an update it makes does not call it again for the same values
  v.view(state);
}

export function subscribe(select, view) {
  const v = {select, view, seen: null};
  views.push(v);
  notify(v);
  return () => views.splice(views.indexOf(v), 1);
}

// Selectors every module uses.
export const isLive = (s = state) => !!s.info && s.info.mode === "live";
// The canvas's smaller side, in canvas units.
export const side = (s = state) => Math.min(s.info.canvas[0], s.info.canvas[1]);
