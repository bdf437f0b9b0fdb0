// The tool bar, built once from GET /api/ops: a button per tool (each a
// ``tool-NAME`` action: its hint says the gesture) and the settings' fields,
// one group per op type that has some, whose values the store keeps.
import { register, toolAction, wire } from "./actions.js";
import { $ } from "./dom.js";
import { update } from "./store.js";

const GESTURE_HELP = {click: "click (drag to size)", line: "drag a line", centre: "drag from the centre", path: "draw a path"};

export function buildToolbar(tools, types) {
  register(tools.map((tool) => toolAction(tool.name, `${tool.name}: ${GESTURE_HELP[tool.gesture]}`)));
  for (const tool of tools) {
    const b = document.createElement("button");
    b.textContent = tool.name; b.dataset.tool = tool.name; b.id = `tool-${tool.name}`;
    b.dataset.action = `tool-${tool.name}`;
    wire(b);
    $("tools").appendChild(b);
  }
  settingFields(types);
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
