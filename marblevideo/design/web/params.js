// The selected op's parameter editors, built from its type's parameters in
// /api/ops: numbers (a field and a slider of the parameter's range law; a key
// at the current time), points (x and y), colours, choices, and JSON for lists
// and keyframe tracks; a bind menu where controllers exist (signals.js).
import { valueAt } from "./ease.js";
import { opButton } from "./oplist.js";
import { edited } from "./recipe.js";
import { sliderRange } from "./range.js";
import { show } from "./sheet.js";
import { bindRow, controlled } from "./signals.js";
import { $, state, isLive, isSignal, isTrack, round3, clone, showError } from "./state.js";

// Kinds edited as a number field (the others: a point, a colour, a choice, or JSON).
const NUMBER_KINDS = ["number", "positive", "nonnegative", "count", "seed"];

// A number's value at the current time (or tt), as the renderer evaluates its track.
export const valueNow = (v, tt = state.t) => valueAt(v, tt);
// The canvas's larger side: what slider ranges scale with.
const size = () => Math.max(state.info.canvas[0], state.info.canvas[1]);
export const rangeOf = (p, v) => sliderRange(p, v, size());

let probe = null;  // a 2D context that spells CSS colours as #rrggbb (made once: it is slow to make)
function hexColor(v) {
  if (Array.isArray(v)) return "#" + v.map((c) => Math.round(c).toString(16).padStart(2, "0")).join("");
  if (/^#[0-9a-f]{6}$/i.test(v)) return v.toLowerCase();
  probe = probe || document.createElement("canvas").getContext("2d");
  probe.fillStyle = String(v);
  return probe.fillStyle;
}
export function input(id, type, value) {
  const el = document.createElement("input");
  el.id = id; el.type = type;
  if (type === "number") el.step = "any";
  el.value = value;
  return el;
}
// The editor's current value of a parameter (what "set key here" keys).
function readParam(p) {
  if (p.kind === "point") return [Number($(`p-${p.name}-x`).value), Number($(`p-${p.name}-y`).value)];
  if (p.kind === "color") return $(`p-${p.name}`).value;
  const el = $(`p-${p.name}`);
  if (el.type === "number") return el.value === "" ? undefined : Number(el.value);
  if (el.tagName === "SELECT") return el.value;
  return el.value.trim() === "" ? undefined : JSON.parse(el.value);
}
export function setParam(i, name, value, shown = state.fields) {
  if (shown !== state.fields) return null;  // Chrome fires "change" as a focused field is removed
  return edited((d) => { if (value === undefined) delete d.ops[i][name]; else d.ops[i][name] = value; });
}
function keyHere(i, p) {
  let v;
  try { v = readParam(p); } catch (e) { showError(`${p.name}: ${e.message}`); return; }
  if (isTrack(v)) { showError(`ops[${i}].${p.name}: type a value (not keys) to set a key at t = ${state.t}`); return; }
  state.fields += 1;  // the value typed is keyed: the panel's fields must not save it again as they blur
  setParam(i, p.name, keyed(state.doc.ops[i][p.name], v));
}
// ``old`` (a value or keys) with a key of value v at the current time.
function keyed(old, v) {
  const t = state.t;
  const keys = isTrack(old) ? old.keys.filter((k) => Math.abs(k.t - t) > 1e-6)
    : (old === undefined || t === 0 ? [] : [{t: 0, v: old}]);
  keys.push({t: round3(t), v});
  keys.sort((x, y) => x.t - y.t);
  return {keys};
}
// A slider for a number, constant or keyed: moved, the frame follows (a draft;
// live: on release), released, it saves the value (keyed: a key at the current time).
function slider(i, p, v, shown) {
  const now = valueNow(v === undefined ? p.default : v);
  if (now === null || now === undefined) return null;
  const [lo, hi, step] = rangeOf(p, now), el = input(`s-${p.name}`, "range", now);
  el.min = lo; el.max = hi; el.step = step; el.value = now;
  el.title = `${p.name}${p.units ? ` (${p.units})` : ""}${isTrack(v) ? ": sets a key at the current time" : ""}`;
  const next = () => {
    const value = Number(el.value), d = clone(state.doc);
    d.ops[i][p.name] = isTrack(v) ? keyed(v, value) : value;
    return [value, d];
  };
  el.addEventListener("input", () => {
    const [value, d] = next(), field = $(`p-${p.name}`);
    if (field && field.type === "number") field.value = value;
    if (!isLive()) show({draft: true, doc: d});
  });
  el.addEventListener("change", () => {
    if (shown !== state.fields) return;
    const [, d] = next();
    setParam(i, p.name, d.ops[i][p.name], shown);
  });
  return el;
}
// The field that edits parameter p of op i, of value v.
function editor(i, p, v, shown) {
  const save = (read) => () => setParam(i, p.name, read(), shown);
  if (isTrack(v) || isSignal(v) || !(NUMBER_KINDS.includes(p.kind) || p.kind === "point" || p.kind === "color" || p.choices)) {
    const field = input(`p-${p.name}`, "text", v === undefined ? "" : JSON.stringify(v));
    field.addEventListener("change", () => {
      let value;
      try { value = readParam(p); } catch (e) { showError(`ops[${i}].${p.name}: invalid JSON: ${e.message}`); return; }
      setParam(i, p.name, value, shown);
    });
    return field;
  }
  if (p.kind === "point") {
    const field = document.createElement("span");
    field.className = "pair";
    const x = input(`p-${p.name}-x`, "number", v ? v[0] : ""), y = input(`p-${p.name}-y`, "number", v ? v[1] : "");
    for (const el of [x, y]) el.addEventListener("change", save(() => readParam(p)));
    field.append(x, y);
    return field;
  }
  if (p.kind === "color") {
    const field = input(`p-${p.name}`, "color", hexColor(v));
    field.addEventListener("change", save(() => field.value));
    return field;
  }
  if (p.choices) {
    const field = document.createElement("select");
    field.id = `p-${p.name}`;
    for (const c of p.choices) field.add(new Option(c, c, false, (v === undefined ? p.default : v) === c));
    field.addEventListener("change", save(() => field.value));
    return field;
  }
  const field = input(`p-${p.name}`, "number", v === undefined ? "" : v);
  field.addEventListener("change", save(() => readParam(p)));
  return field;
}
export function showParams() {
  state.fields += 1;
  const box = $("params");
  box.textContent = "";
  const {selected, doc} = state;
  if (selected === null || !doc.ops[selected]) { $("params-title").textContent = "Parameters"; return; }
  const i = selected, op = doc.ops[i], def = state.types[op.type], shown = state.fields;
  $("params-title").textContent = `ops[${i}] ${op.type}`;
  for (const p of def.params) {
    const label = document.createElement("label");
    const name = document.createElement("span");
    name.textContent = p.name;
    name.title = p.help;
    const v = op[p.name];
    label.append(name, editor(i, p, v, shown));
    if (p.keyable) {
      const key = opButton("key", `set key here: ${p.name} at the current time`, () => keyHere(i, p));
      key.id = `key-${p.name}`;
      // the field keeps the focus: a value typed there is keyed, not saved as a constant first
      key.addEventListener("mousedown", (ev) => ev.preventDefault());
      label.appendChild(key);
    } else label.appendChild(document.createElement("span"));
    box.appendChild(label);
    const range = p.slider ? slider(i, p, v, shown) : null;
    if (range) box.appendChild(range);
    if (controlled() && p.slider && p.keyable) box.appendChild(bindRow(i, p, v, shown));
  }
}
