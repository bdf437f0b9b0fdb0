// The ink colour and the palettes: the colour a new ink op takes, and the
// colours a layout's drops take in turn (the colour chosen first). The store
// holds both (color, palette); the header's fields show and set them.
import { $ } from "./dom.js";
import { update } from "./store.js";

const PALETTES = {
  classic: ["#1d3557", "#b23a48", "#e9c46a", "#2a9d8f", "#f4f1de"],
  turkish: ["#8c1c13", "#bf4342", "#e7d7c1", "#a78a7f", "#735751"],
  sea: ["#03045e", "#0077b6", "#00b4d8", "#90e0ef", "#caf0f8"],
  earth: ["#283618", "#606c38", "#fefae0", "#dda15e", "#bc6c25"],
  mono: ["#000000", "#444444", "#888888", "#cccccc", "#ffffff"],
};
export function inks(s) {
  return [s.color, ...PALETTES[s.palette].filter((x) => x !== s.color)];
}
const setColor = (color) => update(() => ({color}));

export const paletteOf = (s) => [s.color, s.palette];
export function showPalette(s) {
  $("color").value = s.color;
  $("palettes").value = s.palette;
  const box = $("palette");
  if (box.dataset.palette === s.palette) return;
  box.dataset.palette = s.palette;
  box.textContent = "";
  for (const c of PALETTES[s.palette]) {
    const swatch = document.createElement("span");
    swatch.className = "swatch"; swatch.style.background = c; swatch.title = c;
    swatch.addEventListener("click", () => setColor(c));
    box.appendChild(swatch);
  }
}
export function initPalette() {
  for (const name of Object.keys(PALETTES)) $("palettes").add(new Option(name, name));
  $("palettes").addEventListener("change", () => {
    const palette = $("palettes").value;
    update(() => ({palette, color: PALETTES[palette][0]}));
  });
  $("color").addEventListener("input", () => setColor($("color").value));
}
