// The page around the sheet (views of the store): the file's name, the export
// links (of the time shown; the hosts' programs of the design as it stands), the
// error over the sheet, the status line, the mode.
import { $ } from "./dom.js";
import { isLive, update } from "./store.js";

// A host's export is fetched first: a design it cannot carry (motion, a signal,
// too much data) says why over the sheet instead of downloading the error.
for (const a of document.querySelectorAll("a.export-host")) {
  a.addEventListener("click", async (ev) => {
    ev.preventDefault();
    const r = await fetch(a.href);
    if (!r.ok) {
      const answer = await r.json().catch(() => ({error: `${r.status}`}));
      update(() => ({error: `export: ${answer.error}`}));
      return;
    }
    const link = document.createElement("a");
    link.href = URL.createObjectURL(await r.blob());
    link.download = a.download;
    link.click();
    URL.revokeObjectURL(link.href);
  });
}

export const fileOf = (s) => [s.info.file, s.info.mode, s.info.input.kind];
export function showFile(s) {
  $("file").textContent = s.info.file;
  const name = s.info.file.split("/").pop();
  $("export-recipe").download = name;
  for (const a of document.querySelectorAll("a.export-host"))
    a.download = name.replace(/\.json$/i, "") + a.id.replace("export-", ".");
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
