// Signals (live mode, or the designer over a live source): a number bound to a
// signal ({"signal": NAME, "range": [lo, hi]}) shows a meter of y (0..1, GET
// /api/signals, polled while a bind menu is shown); any slider has a bind menu:
// an audio band, an OSC address (typed, or one already received), or learn
// (POST /api/learn: the next control moved, OSC or MIDI, is bound). The binding
// is saved into the recipe like any edit; "not bound" keeps the value the
// parameter has now.
import * as api from "./api.js";
import { rangeOf, valueNow } from "./numbers.js";
import { get, update, isLive } from "./store.js";
import { isSignal, round3 } from "./values.js";

const AUDIO = ["audio.level", "audio.low", "audio.mid", "audio.high"];
let signalState = {values: {}, latest: {}}, signalTimer = null;

// Signals can be bound where controllers exist: live mode, or the designer over a live source.
export function controlled() {
  const {info} = get();
  return isLive() || (!!info && info.input.kind === "live");
}
const setStatus = (status) => update(() => ({status}));

// The bind menu (and meter) of parameter p of op i, of value v; ``save(value)`` saves it.
export function bindRow(i, p, v, save) {
  const row = document.createElement("div");
  row.className = "bind";
  const menu = document.createElement("select");
  menu.id = `bind-${p.name}`;
  menu.title = `bind ${p.name} to a signal`;
  const bound = isSignal(v) ? v.signal : "";
  const names = [...AUDIO, ...Object.keys(signalState.latest).sort()];
  if (bound && !names.includes(bound)) names.push(bound);
  menu.add(new Option(bound ? "not bound" : "bind…", "", false, !bound));
  for (const name of names) menu.add(new Option(name, name, false, name === bound));
  menu.add(new Option("osc:/… (type an address)", "osc"));
  menu.add(new Option("learn: the next control moved", "learn"));
  menu.addEventListener("change", async () => {
    const value = await bindTo(i, p, v, menu.value);
    if (value === null) menu.value = bound;  // nothing chosen: as it was
    else save(value);
  });
  row.appendChild(menu);
  if (isSignal(v)) {
    const meter = document.createElement("span");
    meter.className = "meter"; meter.id = `m-${p.name}`; meter.dataset.path = `ops[${i}].${p.name}`;
    meter.appendChild(document.createElement("i"));
    row.appendChild(meter);
  }
  pollSignals();
  return row;
}
// The value a parameter has now: a signal's from its meter, else as the slider has it.
function numberNow(i, p, v) {
  if (!isSignal(v)) return valueNow(v === undefined ? p.default : v);
  const y = signalState.values[`ops[${i}].${p.name}`] || 0;
  return round3(v.range[0] + (v.range[1] - v.range[0]) * y);
}
// The value a choice of the bind menu gives (null: none chosen after all).
async function bindTo(i, p, v, choice) {
  let name = choice;
  if (choice === "osc") {
    const typed = window.prompt("OSC address (e.g. /fader/1)", "/");
    if (!typed) return null;
    name = `osc:${typed.startsWith("/") ? typed : "/" + typed}`;
  } else if (choice === "learn") {
    name = await learned();
    if (!name) return null;
  }
  const now = numberNow(i, p, v);
  let value = now;
  if (name) {
    const [lo, hi] = isSignal(v) ? v.range : offAtZero(rangeOf(p, now));
    value = {signal: name, range: [lo, hi]};
  }
  return value;
}
// A new binding's range is off at 0: where the slider's range is symmetric
// (-m..m) it binds 0..m, so a fader at its bottom leaves the op at rest rather
// than fully reversed (the range stays editable).
export const offAtZero = ([lo, hi]) => (lo < 0 && hi > 0 ? [0, hi] : [lo, hi]);
// Learn: the name of the next controller message the session receives (null after 30 s).
async function learned() {
  await api.learn();
  setStatus("learn: move a control…");
  for (let n = 0; n < 300; n++) {
    const s = await api.signals();
    if (s.learned) { setStatus(`learned ${s.learned}`); return s.learned; }
    await new Promise((done) => setTimeout(done, 100));
  }
  setStatus("learn: nothing moved");
  return null;
}
// Meters (and the names a bind menu offers) follow the session at 10 Hz while
// a bind menu is shown.
function pollSignals() {
  if (signalTimer !== null) return;
  signalTimer = setTimeout(async () => {
    signalTimer = null;
    if (!document.querySelector(".bind")) return;
    try { signalState = await api.signals(); } catch (e) { return; }
    for (const m of document.querySelectorAll(".meter")) {
      const y = signalState.values[m.dataset.path];
      if (y === undefined) continue;
      m.dataset.y = y.toFixed(3);
      m.firstChild.style.width = `${(100 * y).toFixed(1)}%`;
      m.title = `${m.dataset.path}: ${y.toFixed(3)}`;
    }
    pollSignals();
  }, 100);
}
