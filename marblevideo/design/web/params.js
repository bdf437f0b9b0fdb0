// The selected op's parameter editors (a view of the store), built from its
// type's parameters in /api/ops: numbers (a field and a slider of the
// parameter's range law; a key at the current time), points (x and y),
// colours, choices, keyframe tracks as their list of keys (keys.js) and JSON for
// lists and signals; a bind menu where controllers exist (signals.js).
import { $, button, hexColor, input } from "./dom.js";
import { keyed, setParam } from "./edits.js";
import { keysText, parseField } from "./keys.js";
import { rangeOf, valueNow } from "./numbers.js";
import { clearPreview, sendPreview } from "./livepreview.js";
import { liveGesture } from "./sheet.js";
import { bindRow, controlled } from "./signals.js";
import { get, update, isLive } from "./store.js";
import { isSignal, isTrack, clone } from "./values.js";

// Kinds edited as a number field (the others: a point, a colour, a choice, or JSON).
const NUMBER_KINDS = ["number", "positive", "nonnegative", "count", "seed"];

// The editor's current value of a parameter (what "set key here" keys).
function readParam(p) {
  if (p.kind === "point") return [Number($(`p-${p.name}-x`).value), Number($(`p-${p.name}-y`).value)];
  if (p.kind === "color") return $(`p-${p.name}`).value;
  const el = $(`p-${p.name}`);
  if (el.type === "number") return el.value === "" ? undefined : Number(el.value);
  if (el.tagName === "SELECT") return el.value;
  return parseField(el.value);
}
let fields = 0;  // counts the editors shown: a field removed with a value typed in is dropped
// Save parameter ``name`` of op i from the editors shown as ``shown``.
function save(i, name, value, shown) {
  if (shown !== fields) return null;  // Chrome fires "change" as a focused field is removed
  return setParam(i, name, value);
}
const setError = (error) => update(() => ({error}));
function keyHere(i, p) {
  const {t, doc} = get();
  let v;
  try { v = readParam(p); } catch (e) { setError(`${p.name}: ${e.message}`); return; }
  if (isTrack(v)) { setError(`ops[${i}].${p.name}: type a value (not keys) to set a key at t = ${t}`); return; }
  fields += 1;  // the value typed is keyed: the panel's fields must not save it again as they blur
  setParam(i, p.name, keyed(doc.ops[i][p.name], v, t));
}
// A slider for a number, constant or keyed: moved, the frame follows (a draft;
// live: the live frames, through a preview), released, it saves the value
// (keyed: a key at the current time).
function slider(i, p, v, shown) {
  const now = valueNow(v === undefined ? p.default : v);
  if (now === null || now === undefined) return null;
  const [lo, hi, step] = rangeOf(p, now), el = input(`s-${p.name}`, "range", now);
  el.min = lo; el.max = hi; el.step = step; el.value = now;
  el.title = `${p.name}${p.units ? ` (${p.units})` : ""}${isTrack(v) ? ": sets a key at the current time" : ""}`;
  const next = () => {
    const value = Number(el.value), d = clone(get().doc);
    d.ops[i][p.name] = isTrack(v) ? keyed(v, value, get().t) : value;
    return [value, d];
  };
  el.addEventListener("input", () => {
    const [value, d] = next(), field = $(`p-${p.name}`);
    if (field && field.type === "number") field.value = value;
    if (isLive()) {
      sendPreview(() => d, get().version);  // the live frames follow the slider
      liveGesture(d);  // and the newest one is warped to it meanwhile
    } else update(() => ({preview: {doc: d, draft: true}}));
  });
  el.addEventListener("change", () => {
    const [, d] = next();
    if (isLive()) {
      liveGesture(null);
      clearPreview(null);  // the save replaces the preview
    }
    save(i, p.name, d.ops[i][p.name], shown);
  });
  return el;
}
// The field that edits parameter p of op i, of value v.
function editor(i, p, v, shown) {
  const saved = (read) => () => save(i, p.name, read(), shown);
  if (isTrack(v) || isSignal(v) || !(NUMBER_KINDS.includes(p.kind) || p.kind === "point" || p.kind === "color" || p.choices)) {
    const list = isTrack(v) ? keysText(v) : null;
    const field = input(`p-${p.name}`, "text", v === undefined ? "" : list ?? JSON.stringify(v));
    if (list !== null) field.title = "keys: TIME s: VALUE (EASE) → ...; or a value, set as a key here by \"key\"";
    field.addEventListener("change", () => {
      let value;
      try { value = readParam(p); } catch (e) { setError(`ops[${i}].${p.name}: ${e.message}`); return; }
      save(i, p.name, value, shown);
    });
    return field;
  }
  if (p.kind === "point") {
    const field = document.createElement("span");
    field.className = "pair";
    const x = input(`p-${p.name}-x`, "number", v ? v[0] : ""), y = input(`p-${p.name}-y`, "number", v ? v[1] : "");
    for (const el of [x, y]) el.addEventListener("change", saved(() => readParam(p)));
    field.append(x, y);
    return field;
  }
  if (p.kind === "color") {
    const field = input(`p-${p.name}`, "color", hexColor(v));
    field.addEventListener("change", saved(() => field.value));
    return field;
  }
  if (p.choices) {
    const field = document.createElement("select");
    field.id = `p-${p.name}`;
    for (const c of p.choices) field.add(new Option(c, c, false, (v === undefined ? p.default : v) === c));
    field.addEventListener("change", saved(() => field.value));
    return field;
  }
  const field = input(`p-${p.name}`, "number", v === undefined ? "" : v);
  field.addEventListener("change", saved(() => readParam(p)));
  return field;
}
export const paramsOf = (s) => [s.doc, s.selected, s.types, s.refusals];
export function showParams(s) {
  const shown = fields += 1;
  const box = $("params");
  box.textContent = "";
  const {selected, doc} = s;
  if (selected === null || !doc.ops[selected]) { $("params-title").textContent = "Parameters"; return; }
  const i = selected, op = doc.ops[i], def = s.types[op.type];
  $("params-title").textContent = `ops[${i}] ${op.type}`;
  for (const p of def.params) {
    const label = document.createElement("label");
    const name = document.createElement("span");
    name.textContent = p.name;
    name.title = p.help;
    const v = op[p.name];
    label.append(name, editor(i, p, v, shown));
    if (p.keyable) {
      const key = button("key", `set key here: ${p.name} at the current time`, () => keyHere(i, p));
      key.id = `key-${p.name}`;
      // the field keeps the focus: a value typed there is keyed, not saved as a constant first
      key.addEventListener("mousedown", (ev) => ev.preventDefault());
      label.appendChild(key);
    } else label.appendChild(document.createElement("span"));
    box.appendChild(label);
    const range = p.slider ? slider(i, p, v, shown) : null;
    if (range) box.appendChild(range);
    if (controlled() && p.slider && p.keyable) box.appendChild(bindRow(i, p, v, (value) => save(i, p.name, value, shown)));
  }
}
