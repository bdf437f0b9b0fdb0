// Small DOM helpers every view uses.
export const $ = (id) => document.getElementById(id);
// Whether ``el`` is a field that takes the keys typed (an input of any kind, a
// menu, a text area, a contenteditable): the page's shortcuts leave its keys alone.
export const isField = (el) => !!el && (["INPUT", "SELECT", "TEXTAREA"].includes(el.tagName) || el.isContentEditable);

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

// A colour (#rrggbb, #rgb, a CSS name or [r, g, b]) as the #rrggbb a colour field takes.
let probe = null;  // a 2D context that spells CSS colours as #rrggbb (made once: it is slow to make)
export function hexColor(v) {
  if (Array.isArray(v)) return "#" + v.map((c) => Math.round(c).toString(16).padStart(2, "0")).join("");
  if (/^#[0-9a-f]{6}$/i.test(v)) return v.toLowerCase();
  probe = probe || document.createElement("canvas").getContext("2d");
  probe.fillStyle = String(v);
  return probe.fillStyle;
}
