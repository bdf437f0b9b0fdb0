// Small DOM helpers every view uses.
export const $ = (id) => document.getElementById(id);

// A button of the op list or the editors: ``title`` is also its data-act.
export function button(label, title, action) {
  const b = document.createElement("button");
  b.textContent = label; b.title = title; b.dataset.act = title;
  b.addEventListener("click", (ev) => { ev.stopPropagation(); action(); });
  return b;
}
export function input(id, type, value) {
  const el = document.createElement("input");
  el.id = id; el.type = type;
  if (type === "number") el.step = "any";
  el.value = value;
  return el;
}
