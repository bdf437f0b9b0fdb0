// The warp's WebGL canvas shown as the sheet during a gesture: placed over the
// 2D sheet (the same box, under the overlay) and made visible, a warped frame
// reaches the screen without a readback (readPixels waits for SwiftShader's
// whole draw on the page's thread) or a putImageData. The 2D sheet takes the
// next frame drawn there (the server's) and the WebGL canvas is hidden in the
// same animation frame. ``?glsheet=0`` in the page's address: every warped
// frame read back into the 2D sheet instead (tests, benchmarks).
import { overlay, sheet } from "./view.js";

export const enabled = new URLSearchParams(location.search).get("glsheet") !== "0";
let shown = null, reader = null, fences = [], polling = false;

// ``canvas`` (the warp's, its last draw the frame) shown as the sheet;
// ``read(all)`` gives its pixels ({image, rect}, warp.js read).
export function showWarp(canvas, read) {
  if (shown !== canvas) {
    if (shown) hideWarp();
    canvas.id = "sheet-gl";
    if (canvas.nextSibling !== overlay) overlay.before(canvas);
    canvas.style.visibility = "visible";
  }
  shown = canvas;
  reader = read;
}
// The frame record ``entry`` (record.js) of the draw just made on the shown
// canvas: its drawnAt becomes the first animation frame at which the GPU has
// done the draw (a fence), so latency counts SwiftShader's work.
export function whenDrawn(entry) {
  const gl = shown && shown.getContext("webgl2");
  if (!gl) return;
  fences.push({entry, sync: gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0), gl, at: performance.now()});
  gl.flush();
  if (!polling) { polling = true; requestAnimationFrame(poll); }
}
function poll() {
  const now = performance.now();
  fences = fences.filter(({entry, sync, gl}) => {
    if (gl.getSyncParameter(sync, gl.SYNC_STATUS) !== gl.SIGNALED) return true;
    entry.drawnAt = now;
    gl.deleteSync(sync);
    return false;
  });
  polling = fences.length > 0;
  if (polling) requestAnimationFrame(poll);
}
// Whether the GPU has two frames shown still to draw (for at most BUSY ms: a
// fence that never comes, a lost context, does not stop the frames): the next
// draw waits, so at most one is queued behind the one being drawn. (Unbounded,
// SwiftShader ran 3-4 queued draws at once on two busy cores: live --preview's
// latency p95 146-309 ms; one at a time left its GPU idle between frames: median
// 86-98 ms; two, 63-78 ms and p95 121-169 ms. BENCHMARKS.md.)
const BUSY = 250;
export const gpuBusy = () => fences.length > 1 && performance.now() - fences[0].at < BUSY;
// The 2D sheet shown again (its caller has just drawn a frame there).
export function hideWarp() {
  if (shown) shown.style.visibility = "hidden";
  shown = null;
  reader = null;
}
export const warpShown = () => shown !== null;
// The pixels the sheet shows now, whichever canvas shows them: an ImageData
// (a copy) of the sheet's size.
export function shownPixels() {
  if (!shown) return sheet.getContext("2d").getImageData(0, 0, sheet.width, sheet.height);
  const { image } = reader(true);
  return new ImageData(new Uint8ClampedArray(image.data), image.width, image.height);
}
// Before the 2D sheet is drawn on or copied while the warp's canvas shows: its
// frame into the 2D sheet, and the 2D sheet shown.
export function settleWarp() {
  if (!shown) return;
  const { image } = reader(true);
  if (image.width === sheet.width && image.height === sheet.height) sheet.getContext("2d").putImageData(image, 0, 0);
  hideWarp();
}
