// The op list (a view of the store): each op's name (select it), hide, solo,
// up, down and delete.
import { $, button } from "./dom.js";
import { move, remove, select, toggleHidden, toggleSolo } from "./edits.js";
import { isLive } from "./store.js";

export const opListOf = (s) => [s.doc, s.selected, s.solo, s.refusals];
export function showOps(s) {
  const list = $("oplist");
  list.textContent = "";
  s.doc.ops.forEach((op, i) => {
    const li = document.createElement("li");
    li.id = `op-${i}`;
    li.classList.toggle("selected", i === s.selected);
    li.classList.toggle("hidden", !!op.hidden || (s.solo !== null && s.solo !== i));
    const name = document.createElement("span");
    name.className = "name";
    name.textContent = `${i} ${op.type}`;
    name.addEventListener("click", () => select(i));
    li.append(name);
    li.append(button(op.hidden ? "show" : "hide", "hide", () => toggleHidden(i)));
    if (!isLive(s)) li.append(button(s.solo === i ? "all" : "solo", "solo", () => toggleSolo(i)));  // the live frame is of the whole recipe
    li.append(
      button("↑", "up", () => move(i, -1)),
      button("↓", "down", () => move(i, 1)),
      button("✕", "delete", () => remove(i)));
    list.appendChild(li);
  });
}
