// The page's actions, one table: each has a name, the keys that perform it
// ("Mod" is Ctrl or Cmd; none: a button or the pointer only), a one-line hint,
// perform(state) and enabled(state) (and, for a mode such as a tool, on(state)).
// The keyboard shortcuts, the buttons' hints (title), clicks and disabled or
// "on" looks are all built from it: a button names its action (data-action).
import { isField } from "./dom.js";
import { clearOps, remove, select } from "./edits.js";
import { redo, undo } from "./recipe.js";
import { get, update } from "./store.js";
import { togglePlay } from "./timeline.js";

const always = () => true;
const registry = new Map();
// Add ``actions``; a key another action has already is refused (an error: no two actions share one).
export function register(actions) {
  for (const a of actions) {
    for (const key of a.keys || []) {
      const other = [...registry.values()].find((b) => b.keys.some((k) => k.toLowerCase() === key.toLowerCase()));
      if (other) throw new Error(`actions: key ${key} of ${a.name} is ${other.name}'s already`);
    }
    registry.set(a.name, {keys: [], enabled: always, ...a});
  }
}
register([
  {name: "undo", keys: ["Mod+Z"], hint: "undo", perform: undo, enabled: (s) => s.undo.length > 0},
  {name: "redo", keys: ["Mod+Shift+Z", "Mod+Y"], hint: "redo", perform: redo, enabled: (s) => s.redo.length > 0},
  {name: "delete", keys: ["Delete", "Backspace"], hint: "delete the selected op",
    perform: (s) => remove(s.selected), enabled: (s) => s.selected !== null},
  {name: "deselect", keys: ["Escape"], hint: "deselect the op (its handles go: a press there draws)",
    perform: () => select(null), enabled: (s) => s.selected !== null},
  {name: "move", keys: ["M"], hint: "move mode: drag the selected op's points (or hold Alt)",
    perform: () => update((s) => ({moving: !s.moving})), on: (s) => s.moving},
  {name: "clear", hint: "remove every op (undoable)", perform: clearOps,
    enabled: (s) => s.doc !== null && s.doc.ops.length > 0},
  {name: "play", hint: "play or pause", perform: togglePlay},
]);
// A tool's action: it makes ``name`` the active tool (``key``: its shortcut, or "").
export const toolAction = (name, hint, key = "") => ({
  name: `tool-${name}`, hint, keys: key ? [key] : [], perform: () => update(() => ({tool: name})),
  on: (s) => s.tool === name,
});

// "Mod+Shift+Z" as a hint says it: "Ctrl-Shift-Z".
const spelled = (key) => key.replace("Mod", "Ctrl").replaceAll("+", "-");
export const spelledKeys = (a) => a.keys.map(spelled).join(", ");
export const hintOf = (a) => (a.keys.length ? `${a.hint} (${a.keys.map(spelled).join(", ")})` : a.hint);
function matches(key, ev) {
  const parts = key.split("+"), name = parts.pop();
  const mod = parts.includes("Mod"), shift = parts.includes("Shift");
  if (mod !== (ev.ctrlKey || ev.metaKey) || (mod && shift !== ev.shiftKey)) return false;
  return ev.key.toLowerCase() === name.toLowerCase();
}
export function perform(name) {
  const a = registry.get(name), s = get();
  if (a.enabled(s)) a.perform(s);
}
function onKey(ev) {
  if (isField(ev.target)) return;
  for (const a of registry.values()) {
    const key = a.keys.find((k) => matches(k, ev));
    if (key === undefined) continue;
    if (key.startsWith("Mod")) ev.preventDefault();
    perform(a.name);
    return;
  }
}
// Every action with keys, as [keys spelled, hint], in the order registered (the page's list of keys).
export const keyList = () => [...registry.values()].filter((a) => a.keys.length).map((a) => [spelledKeys(a), a.hint]);
// Wire ``el`` (a button) to its action: its hint and its click.
export function wire(el) {
  const a = registry.get(el.dataset.action);
  el.title = hintOf(a);
  el.addEventListener("click", () => perform(a.name));
}
export function initActions() {
  for (const el of document.querySelectorAll("[data-action]")) wire(el);
  document.addEventListener("keydown", onKey);
}
export const actionsOf = (s) => [s.undo, s.redo, s.selected, s.tool, s.doc, s.moving];
export function showActions(s) {
  for (const el of document.querySelectorAll("[data-action]")) {
    const a = registry.get(el.dataset.action);
    el.disabled = !a.enabled(s);
    if (a.on) el.classList.toggle("on", a.on(s));
  }
}
