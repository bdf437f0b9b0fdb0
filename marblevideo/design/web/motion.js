// Motion: the recipe's ``motion`` block (what moves in the input stirs the
// ink). "on" adds the block (its fields at their defaults) or removes it; each
// field is saved into the recipe as any edit (a refusal is shown, and the fields
// show the saved recipe again). The fields and their bounds come from GET
// /api/motion. Over frames only (live mode, the designer over a live source or
// a video: the strokes come from its frames): a meter of the motion seen (level,
// 0..1) and "show", which draws the regions followed and the motion strokes
// over the sheet (overlay.js); /api/motion is polled at 10 Hz into the store
// (``motion``), its regions and strokes only while shown.
import * as api from "./api.js";
import { $ } from "./dom.js";
import { edited } from "./recipe.js";
import { get, isLive, update } from "./store.js";

// ``width`` is a pair [min, max]: two inputs, motion-width-0 and motion-width-1.
const inputsOf = (f) => (Array.isArray(f.default) ? f.default.map((_, k) => `motion-${f.name}-${k}`) : [`motion-${f.name}`]);

let fields = [];  // the block's fields, as /api/motion describes them (read once)
export async function initMotion() {
  const first = await api.motion();
  fields = first.fields;
  update(() => ({motion: first}));
  $("motion-panel").hidden = false;
  for (const f of fields) {
    const label = document.createElement("label");
    label.title = f.help;
    label.append(f.name);
    const box = document.createElement("span");
    box.className = "pair";
    for (const id of inputsOf(f)) {
      const el = document.createElement("input");
      el.id = id; el.type = "number"; el.step = f.integer ? "1" : "any";
      if (f.minimum !== undefined) el.min = f.minimum;
      if (f.maximum !== undefined) el.max = f.maximum;
      el.addEventListener("change", () => setField(f));
      box.append(el);
    }
    label.append(box);
    $("motion-fields").append(label);
  }
  $("motion-on").addEventListener("change", () => setMotion($("motion-on").checked));
  $("motion-show").addEventListener("change", () => update(() => ({showMotion: $("motion-show").checked})));
  const tracked = isLive() || ["live", "video"].includes(get().info.input.kind);
  for (const id of ["motion-level", "motion-show-label"]) $(id).hidden = !tracked;
  if (tracked) pollMotion();
}
function pollMotion() {
  setTimeout(async () => {
    try {
      const m = await api.motion(get().showMotion);  // the shapes only while they are shown
      update(() => ({motion: m}));
    } catch (e) { /* offline: poll says it */ }
    pollMotion();
  }, 100);
}
// The block added (empty: every field at its default) or removed.
function setMotion(on) {
  return edited((d) => { if (on) d.motion = d.motion || {}; else delete d.motion; });
}
// Field ``f`` as its inputs have it (every input empty: the field removed, its
// default; one side of a pair empty: that side's default).
function setField(f) {
  const values = inputsOf(f).map((id) => $(id).value.trim());
  const numbers = values.map((v, k) => (v !== "" ? Number(v) : Array.isArray(f.default) ? f.default[k] : f.default));
  const value = values.every((v) => v === "") ? undefined : (values.length > 1 ? numbers : numbers[0]);
  return edited((d) => {
    const m = {...(d.motion || {})};
    if (value === undefined) delete m[f.name]; else m[f.name] = value;
    d.motion = m;
  });
}

// The fields: the saved recipe's values (the defaults as placeholders), again after a refusal.
// A field the hand is in keeps what is typed, unless a save was just refused.
let refusalsShown = 0;
export const motionFieldsOf = (s) => [s.doc && s.doc.motion, s.refusals, s.motion !== null];
export function showMotionFields(s) {
  if (!s.motion) return;
  const block = s.doc.motion, refused = s.refusals !== refusalsShown;
  refusalsShown = s.refusals;
  $("motion-on").checked = block !== undefined;
  for (const f of fields) {
    const value = block && block[f.name] !== undefined ? block[f.name] : null;
    inputsOf(f).forEach((id, k) => {
      const el = $(id);
      const shown = Array.isArray(f.default) ? (value && value[k]) : value;
      if (refused || document.activeElement !== el) el.value = shown === null || shown === undefined ? "" : shown;
      el.placeholder = Array.isArray(f.default) ? f.default[k] : f.default;
      el.disabled = block === undefined;
    });
  }
}
// The meter of the motion seen (level, 0..1, of the last frame).
export const motionLevelOf = (s) => [s.motion];
export function showMotionLevel(s) {
  const level = s.motion ? s.motion.level : 0, meter = $("motion-level");
  meter.dataset.level = level.toFixed(3);
  meter.firstChild.style.width = `${(100 * level).toFixed(1)}%`;
  meter.title = `motion seen: ${level.toFixed(3)}`;
}
