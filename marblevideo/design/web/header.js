// The page around the sheet (views of the store): the file's name, the export
// links (of the time shown), the error over the sheet, the status line, the mode.
import { $ } from "./dom.js";
import { isLive } from "./store.js";

export const fileOf = (s) => [s.info.file, s.info.mode, s.info.input.kind];
export function showFile(s) {
  $("file").textContent = s.info.file;
  $("export-recipe").download = s.info.file.split("/").pop();
  $("export-svg").style.display = s.info.input.kind === "blank" ? "" : "none";
  $("export-png").download = isLive(s) ? "frame.jpg" : "design.png";
  $("live-controls").hidden = !isLive(s);
  document.body.dataset.mode = s.info.mode || "design";
}
export const exportsOf = (s) => [s.t, s.info.mode];
export function showExports(s) {
  const t = s.t.toFixed(3);
  $("export-png").href = isLive(s) ? "/frame.jpg" : `/api/frame.png?t=${t}`;
  $("export-svg").href = `/api/design.svg?t=${t}`;
}
export const messagesOf = (s) => [s.error, s.status];
export function showMessages(s) {
  const e = $("error");
  e.textContent = s.error || "";
  e.style.display = s.error ? "block" : "none";
  $("status").textContent = s.status;
}
