// The op list: each op's name (select it), hide, solo, up, down and delete.
import { showParams } from "./params.js";
import { edited } from "./recipe.js";
import { drawHandles, show } from "./sheet.js";
import { $, state, isLive } from "./state.js";

export function opButton(label, title, action) {
  const b = document.createElement("button");
  b.textContent = label; b.title = title; b.dataset.act = title;
  b.addEventListener("click", (ev) => { ev.stopPropagation(); action(); });
  return b;
}
export function showOps() {
  const list = $("oplist");
  list.textContent = "";
  state.doc.ops.forEach((op, i) => {
    const li = document.createElement("li");
    li.id = `op-${i}`;
    li.classList.toggle("selected", i === state.selected);
    li.classList.toggle("hidden", !!op.hidden || (state.solo !== null && state.solo !== i));
    const name = document.createElement("span");
    name.className = "name";
    name.textContent = `${i} ${op.type}`;
    name.addEventListener("click", () => { state.selected = i; showOps(); drawHandles(); });
    li.append(name);
    li.append(opButton(op.hidden ? "show" : "hide", "hide", () => toggleHidden(i)));
    if (!isLive()) {  // the live frame is of the whole recipe
      const solo = () => { state.solo = state.solo === i ? null : i; showOps(); show(); };
      li.append(opButton(state.solo === i ? "all" : "solo", "solo", solo));
    }
    li.append(
      opButton("↑", "up", () => move(i, -1)),
      opButton("↓", "down", () => move(i, 1)),
      opButton("✕", "delete", () => remove(i)));
    list.appendChild(li);
  });
  $("undo").disabled = !state.undoStack.length;
  $("redo").disabled = !state.redoStack.length;
  showParams();
}
function move(i, step) {
  const j = i + step;
  if (j < 0 || j >= state.doc.ops.length) return;
  if (state.selected === i) state.selected = j;
  edited((d) => { [d.ops[i], d.ops[j]] = [d.ops[j], d.ops[i]]; });
}
// Hide is saved: "hidden": true keeps the op in the file and out of every render.
function toggleHidden(i) {
  edited((d) => { if (d.ops[i].hidden) delete d.ops[i].hidden; else d.ops[i].hidden = true; });
}
export function remove(i) {
  const {selected} = state;
  if (selected !== null && selected >= i) state.selected = selected === i ? null : selected - 1;
  if (state.solo === i) state.solo = null;
  edited((d) => { d.ops.splice(i, 1); });
}
