// The ink colour and the palettes: the colour a new ink op takes, and the
// colours a layout's drops take in turn (the colour chosen first).
import { $ } from "./state.js";

const PALETTES = {
  classic: ["#1d3557", "#b23a48", "#e9c46a", "#2a9d8f", "#f4f1de"],
  turkish: ["#8c1c13", "#bf4342", "#e7d7c1", "#a78a7f", "#735751"],
  sea: ["#03045e", "#0077b6", "#00b4d8", "#90e0ef", "#caf0f8"],
  earth: ["#283618", "#606c38", "#fefae0", "#dda15e", "#bc6c25"],
  mono: ["#000000", "#444444", "#888888", "#cccccc", "#ffffff"],
};
const palette = () => PALETTES[$("palettes").value];
export const color = () => $("color").value;
export function inks() {
  const c = color();
  return [c, ...palette().filter((x) => x !== c)];
}
function setColor(c) { $("color").value = c; }
function showPalette() {
  const box = $("palette");
  box.textContent = "";
  for (const c of palette()) {
    const s = document.createElement("span");
    s.className = "swatch"; s.style.background = c; s.title = c;
    s.addEventListener("click", () => setColor(c));
    box.appendChild(s);
  }
}
export function initPalette() {
  for (const name of Object.keys(PALETTES)) $("palettes").add(new Option(name, name));
  $("palettes").addEventListener("change", () => { showPalette(); setColor(palette()[0]); });
  showPalette();
}
