"""The page's WebGL2 warp (marblevideo/design/web/warp.js) driven in a real
headless Chromium: a tiny static server for the web folder, Chromium launched
with SwiftShader allowed, and :func:`warp_frames`, which uploads a base picture,
draws ops at times and reads the canvas back (RGBA uint8, top row first)."""

from __future__ import annotations

import base64

import numpy as np
import pytest

from benchmarks.webfolder import serve_web  # noqa: F401 (the tests take it here)

SETUP = """async ([w, h, b64]) => {
  const warp = await import("/web/warp.js");
  const canvas = document.createElement("canvas");
  canvas.width = w; canvas.height = h;
  document.body.appendChild(canvas);
  const W = warp.createWarp(canvas);
  if (!W) return false;
  const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
  W.setBase(new ImageData(new Uint8ClampedArray(bytes.buffer), w, h), w, h);
  window.W = W;
  return true;
}"""

_PIXELS = """const px = W.readPixels();
  let s = "";
  const n = 0x8000;
  for (let i = 0; i < px.length; i += n) s += String.fromCharCode(...px.subarray(i, i + n));
  return btoa(s);"""

#: The warp canvas' pixels as it is now, base64 (RGBA, top row first).
READ = "() => {\n  " + _PIXELS + "\n}"

DRAW = (
    """([op, t, bg, edges, toCanvas, toBase]) => {
  W.setGeometry(toCanvas, toBase);
  if (!W.draw(op, t, bg, edges)) return null;
  """
    + _PIXELS
    + "\n}"
)


ABOVE = """(b64) => {
  if (b64 === null) { W.setAbove(null); return; }
  const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
  W.setAbove(new Float32Array(bytes.buffer));
}"""


ANSWER_SECONDS = 180

_START = """([src, arg]) => {
  window.__answer = undefined;
  setTimeout(() => Promise.resolve().then(() => (0, eval)(src)(arg)).then(
    (v) => { window.__answer = {v: v === undefined ? null : v}; },
    (e) => { window.__answer = {e: String((e && e.stack) || e)}; }), 0);
}"""


def answer(page, script: str, arg=None):
    """``page.evaluate(script, arg)``, bounded: Playwright's evaluate waits for
    ever, and a page that stops answering (once in CI, Chromium spun for 17 min)
    would stall the whole run. After :data:`ANSWER_SECONDS` the page is closed
    (its renderer with it) and the test fails saying so; the module's fixture
    opens a new page for the next test."""
    page.evaluate(_START, [script, arg])
    try:
        page.wait_for_function(
            "window.__answer !== undefined", polling=10, timeout=ANSWER_SECONDS * 1000
        )
    except Exception as e:  # playwright's TimeoutError
        page.close(run_before_unload=False)
        pytest.fail(f"the page did not answer in {ANSWER_SECONDS} s: {script[:60]!r}... ({e})")
    got = page.evaluate("window.__answer")
    if "e" in got:
        raise AssertionError(f"the page threw: {got['e']}")
    return got["v"]


def set_above(page, above: np.ndarray | None) -> None:
    """The map of the ops above, (H, W, 4) float32 (see warp.js' setAbove), or None."""
    data = None if above is None else base64.b64encode(above.astype(np.float32).tobytes()).decode()
    answer(page, ABOVE, data)


def setup_warp(page, base: np.ndarray) -> bool:
    """Make a warp on a canvas of the base's size with ``base`` (H, W, 4) uint8."""
    h, w = base.shape[:2]
    b64 = base64.b64encode(np.ascontiguousarray(base).tobytes()).decode()
    return bool(answer(page, SETUP, [w, h, b64]))


def warp_frame(
    page, op, t, shape, background="#ffffff", edges="clamp", to_canvas=None, to_base=None
):
    """The warp's picture of ``op`` at ``t`` (H, W, 4) uint8, or None when it cannot."""
    h, w = shape[:2]
    to_canvas = to_canvas or [1, 1, 0, 0]
    to_base = to_base or [1, 1, 0, 0]
    out = answer(page, DRAW, [op, t, background, edges, to_canvas, to_base])
    if out is None:
        return None
    return np.frombuffer(base64.b64decode(out), np.uint8).reshape(h, w, 4)
