// The tool bar, built once from GET /api/ops: a button per tool (each a
// ``tool-NAME`` action with the tool's key, shown on the button, and its hint:
// what it makes and the gesture) and the settings' fields, one group per op
// type that has some, whose values the store keeps; and the page's list of keys.
import { keyList, register, toolAction, wire } from "./actions.js";
import { $ } from "./dom.js";
import { update } from "./store.js";
import { drawsInTime } from "./tools.js";

const GESTURE_HELP = {click: "click (drag to size)", line: "drag a line", centre: "drag from the centre", path: "draw a path"};
const IN_TIME = "draw: the ink follows the stylus at the pace drawn, the time moving with it (after release the time shown is the stroke's end)";
const hintFor = (tool, types) => `${tool.name}: ${tool.hint}; ${drawsInTime(tool, types) ? IN_TIME : GESTURE_HELP[tool.gesture]}`;

export function buildToolbar(tools, types) {
  register(tools.map((tool) => toolAction(tool.name, hintFor(tool, types), tool.key)));
  for (const tool of tools) {
    const b = document.createElement("button");
    b.textContent = tool.name; b.dataset.tool = tool.name; b.id = `tool-${tool.name}`;
    b.dataset.action = `tool-${tool.name}`;
    if (tool.key) { const k = document.createElement("kbd"); k.textContent = tool.key; b.append(" ", k); }
    wire(b);
    $("tools").appendChild(b);
  }
  settingFields(types);
  showKeys();
}
// The list of keys (every action that has one) in the page's help.
function showKeys() {
  const list = $("keys");
  list.replaceChildren();
  for (const [keys, hint] of keyList()) {
    const dt = document.createElement("dt"), dd = document.createElement("dd"), k = document.createElement("kbd");
    k.textContent = keys; dt.append(k); dd.textContent = hint;
    list.append(dt, dd);
  }
}
const setSetting = (key, value) => update((s) => ({settings: {...s.settings, [key]: value}}));
// The settings' fields after the tools; each typed value is kept as typed (tools.js reads it).
function settingFields(types) {
  let after = $("tools");
  for (const [type, def] of Object.entries(types)) {
    if (!def.settings.length) continue;
    const box = document.createElement("span");
    box.id = `${type}-controls`;
    box.title = `${type} tools: ${def.settings.map((s) => s.help).join(", ")} (canvas units; empty: from the canvas)`;
    for (const s of def.settings) {
      const f = document.createElement("input"), key = `${type}-${s.name}`;
      f.id = key; f.type = "number"; f.step = "any"; f.value = s.initial;
      f.style.width = "4.5em"; f.placeholder = "auto"; f.title = s.help;
      if (s.low !== null) f.min = s.low;
      if (s.high !== null) f.max = s.high;
      setSetting(key, f.value);
      f.addEventListener("input", () => setSetting(key, f.value));
      box.append(` ${s.name} `, f);
    }
    after.after(box);
    after = box;
  }
}
