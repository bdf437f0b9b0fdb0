"""Three tulips and a scribble drawn with the designer's tools, as a person
would, in Chromium (Playwright): on a blank 600x400 sheet, for each tulip three
concentric drops (the drop tool, key D, each dragged out from the same centre to
its radius, a swatch's colour each), then a stroke (key P) drawn up through
them; last a wavy scribble across all three. Strokes are drawn in time (their
``times``), so the recipe replays them at the pace drawn.

    python -m benchmarks.drawing [--headed] [--slow 2] [--out out]

writes ``OUT/tulips.json`` (the recipe drawn) and ``OUT/tulips.png`` (the
sheet's exact frame at the end). ``--headed`` shows the browser (a display is
needed); ``--slow`` stretches every pause. tests/test_drawing_browser.py draws
the same with :func:`draw` and checks that no gesture was lost.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
import time
from pathlib import Path

from .common import ENV, ROOT

SIZE = (600, 400)
#: The tulips' centres and their drops' radii (outermost first) and colours.
CENTRES = [(150, 230), (300, 230), (450, 230)]
DROPS = [(70, "#b23a48"), (48, "#e9c46a"), (26, "#1d3557")]


def plan() -> list[dict]:
    """The gestures, in frame pixels (the sheet's frame is the canvas): each
    ``{"key": tool key, "color": swatch or None, "points": [...], "pause": s}``."""
    out = []
    for cx, cy in CENTRES:
        for r, color in DROPS:
            drag = [(cx + r * k / 8, cy) for k in range(9)]
            out.append({"key": "d", "color": color, "points": drag, "pause": 0.02})
        up = [(cx + 6 * math.sin(k / 5), cy + 110 - 220 * k / 40) for k in range(41)]
        out.append({"key": "p", "color": None, "points": up, "pause": 0.015})
    scribble = [(40 + 13 * k, 230 + 90 * math.sin(k / 2.7)) for k in range(41)]
    out.append({"key": "p", "color": None, "points": scribble, "pause": 0.015})
    return out


def draw(page, client, gestures: list[dict], slow: float = 1.0) -> list[dict]:
    """Draw ``gestures`` on ``page`` (``client(px, py)``: the page point over frame
    pixel (px, py)) without waiting for saves; for each, the time shown at the
    press (``t``) and the seconds from the press to the release (``held``)."""
    done = []
    for g in gestures:
        page.keyboard.press(g["key"])
        if g["color"]:
            page.click(f".swatch[title='{g['color']}']")
        first, *rest = g["points"]
        page.mouse.move(*client(*first))
        t = page.evaluate("designer.state.t")
        pressed = time.monotonic()
        page.mouse.down()
        for p in rest:
            time.sleep(g["pause"] * slow)
            page.mouse.move(*client(*p))
        page.mouse.up()
        done.append({"t": t, "held": time.monotonic() - pressed})
        time.sleep(0.05 * slow)
    return done


def _exact_shown(page, ops: int) -> None:
    """Wait until the sheet shows the exact frame of the saved recipe of ``ops`` ops."""
    page.wait_for_function(
        """(n) => { const d = document.getElementById('sheet').dataset;
            return designer.state.doc.ops.length === n && !designer.state.saving
                && d.draft === '0' && d.version === String(designer.state.version); }""",
        arg=ops,
        timeout=60000,
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.drawing", description=__doc__)
    p.add_argument("--headed", action="store_true", help="show the browser")
    p.add_argument("--slow", type=float, default=1.0, help="stretch every pause by this")
    p.add_argument("--out", default="out", help="folder for tulips.json and tulips.png")
    args = p.parse_args(argv)
    from playwright.sync_api import sync_playwright

    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    recipe = out / "tulips.json"
    recipe.unlink(missing_ok=True)
    cmd = [sys.executable, "-m", "marblevideo", "design", "--ops", str(recipe), "--canvas",
           f"{SIZE[0]}x{SIZE[1]}", "--no-browser", "--port", "0", "--duration", "600"]  # fmt: skip
    app = subprocess.Popen(cmd, cwd=ROOT, env=ENV, stdout=subprocess.PIPE, text=True)
    try:
        url = app.stdout.readline().split(" ", 1)[1].strip()
        with sync_playwright() as pw:
            chromium = shutil.which("chromium")
            browser = pw.chromium.launch(
                executable_path=chromium, headless=not args.headed, args=["--no-sandbox"]
            )
            page = browser.new_page(viewport={"width": 1300, "height": 900})
            page.goto(url)
            page.wait_for_selector("body[data-ready='1']")
            box = page.locator("#overlay").bounding_box()

            def client(px, py):
                return box["x"] + px * box["width"] / SIZE[0], box["y"] + py * box["height"] / SIZE[
                    1
                ]

            gestures = plan()
            draw(page, client, gestures, args.slow)
            _exact_shown(page, len(gestures))
            page.keyboard.press("Escape")  # deselected: no handles over the picture
            page.wait_for_function("designer.state.selected === null")
            page.locator("#sheet").screenshot(path=str(out / "tulips.png"))
            browser.close()
    finally:
        app.terminate()
        app.wait(30)
    ops = json.loads(recipe.read_text())["ops"]
    print(f"drew {len(ops)} ops ({', '.join(o['type'] for o in ops)}) into {recipe}")
    print(f"the sheet at the end: {out / 'tulips.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
