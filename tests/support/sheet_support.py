"""The designer's sheet driven in a real headless Chromium, for the browser tests:
``marblevideo design`` and its page (sheet_page), its exact frames (exact), the
pixels the sheet shows now from whichever canvas shows them (the 2D sheet, or
the warp's WebGL canvas during a gesture: ``designer.sheetPixels``), what the
page says they show (``window.marbleShown``), and the server's exact render of
that (server_render)."""

from __future__ import annotations

import base64
import json
import struct
import urllib.request
from contextlib import contextmanager

import cv2
import numpy as np
from live_helpers import LiveProcess

#: The sheet's pixels as it shows them, as a PNG data URL (JS expression).
SHOWN_PNG = """(() => { const d = designer.sheetPixels(), c = document.createElement('canvas');
    c.width = d.width; c.height = d.height; c.getContext('2d').putImageData(d, 0, 0);
    return c.toDataURL('image/png'); })()"""


#: A design whose detail a pixel resolves (the mid-gesture agreement is of such
#: designs: on a nonpareil at the screen's size the exact render's own
#: antialiasing is at the pixel's scale, and no picture resampled agrees with it
#: within 8 levels; see docs/architecture.md).
DROPS = {
    "marblevideo": 1,
    "canvas": [320, 240],
    "background": "#f4f1de",
    "ops": [
        {"type": "drop", "center": [160, 120], "radius": 60, "color": "#1d3557"},
        {"type": "drop", "center": [100, 90], "radius": 30, "color": "#e63946"},
        {"type": "wave", "angle": 0, "amplitude": 8, "wavelength": 90, "phase": 0},
    ],
}


def decode_png(url: str) -> np.ndarray:
    """A PNG data URL as RGB."""
    data = base64.b64decode(url.split(",", 1)[1])
    return cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)[:, :, ::-1]


#: A mid-gesture frame against the exact render: share of pixels within LEVELS.
LEVELS, SHARE = 8, 0.98
#: The sheet's exact frame against another exact render of the same view: the
#: renderer is adaptive on blank sheets, and after a busy frame takes the full
#: pattern for a while (marblevideo.opencl.renderer), so two renders of one
#: recipe may differ on a few ink edges.
EXACT_SHARE = 0.995


@contextmanager
def sheet_page(browser, folder, *args, dpr=1, size=(760, 520), query=""):
    """``marblevideo design ARGS`` and its page (``dpr``: device_scale_factor),
    once it shows an exact frame: yields (page, app, errors)."""
    app = LiveProcess(
        *args, "--no-browser", "--port", "0", "--duration", "150", cwd=folder, command="design"
    )
    errors: list[str] = []
    try:
        viewport = {"width": size[0], "height": size[1]}
        page = browser.new_page(viewport=viewport, device_scale_factor=dpr)
        page.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
        page.goto(app.url + query)
        page.wait_for_selector("body[data-ready='1']")
        exact(page)
        yield page, app, errors
        page.close()
    finally:
        assert app.stop() == 0


def exact(page, after: int = 0) -> None:
    """Wait for an exact frame of the saved recipe and of the view the page now
    holds, drawn after frame ``after`` (a frame asked for an earlier view, e.g.
    between two keys, may land after a later key's press under load)."""
    page.wait_for_function(
        """(n) => { const f = window.marbleFrames.at(-1), s = window.marbleShown;
            const d = document.getElementById('sheet').dataset, v = designer.state.view;
            return f && f.n > n && f.kind === 'exact'
                && d.version === String(designer.state.version)
                && (!v || (s && s.view.every((a, i) => Math.abs(a - v[i]) < 1e-9))); }""",
        arg=after,
        timeout=60000,
    )


def comb_pressed(page, moves: int) -> tuple[float, float]:
    """The comb tool pressed at 30% across and 40% down the sheet and moved
    ``moves`` times by (12, 5) CSS px, the button left down: the press's page point."""
    page.click("#tool-comb")
    box = page.locator("#overlay").bounding_box()
    x0, y0 = box["x"] + box["width"] * 0.3, box["y"] + box["height"] * 0.4
    page.mouse.move(x0, y0)
    page.mouse.down()
    for i in range(1, moves + 1):
        page.mouse.move(x0 + 12 * i, y0 + 5 * i)
    return x0, y0


def shown(page) -> tuple[np.ndarray, dict, dict]:
    """The sheet's pixels (RGB), what the page says they show, and its last frame's record."""
    got = page.evaluate(
        "() => ({png: "
        + SHOWN_PNG
        + """,
                   shown: window.marbleShown, frame: window.marbleFrames.at(-1)})"""
    )
    return decode_png(got["png"]), got["shown"], got["frame"]


def shown_when(page, condition: str) -> tuple[np.ndarray, dict, dict]:
    """:func:`shown`, read in the same task as ``condition`` (JS, of the last
    frame record ``f``) is first seen true, so no later frame comes between."""
    got = page.evaluate(
        f"""() => new Promise((resolve, reject) => {{
            const until = performance.now() + 60000;
            const look = () => {{
                const f = window.marbleFrames.at(-1);
                if (performance.now() > until) {{
                    reject(new Error(`no frame where {condition} in 60 s: ${{JSON.stringify(f)}}`));
                    return;
                }}
                if (!({condition})) {{ requestAnimationFrame(look); return; }}
                resolve({{png: {SHOWN_PNG},
                          shown: window.marbleShown, frame: f}});
            }};
            look();
        }})"""
    )
    return decode_png(got["png"]), got["shown"], got["frame"]


def server_render(app, shown: dict) -> np.ndarray:
    """The server's exact render (RGB) of what ``shown`` describes."""
    view = ",".join(repr(v) for v in shown["view"])
    query = f"t={shown['t']}&w={shown['w']}&h={shown['h']}&view={view}"
    request = urllib.request.Request(
        f"{app.url}api/frame.rgba?{query}",
        data=json.dumps(shown["doc"]).encode(),
        headers={"Content-Type": "application/json"},
    )
    raw = urllib.request.urlopen(request, timeout=60).read()
    w, h = struct.unpack("<II", raw[:8])
    return np.frombuffer(raw[8:], np.uint8).reshape(h, w, 4)[:, :, :3]
