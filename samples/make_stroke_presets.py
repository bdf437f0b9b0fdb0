"""Write the free-hand stroke presets: samples/tulip.json, heart.json,
french-curl.json, bird.json and gesture.json, blank-sheet designs drawn with
``stroke`` s.

``python samples/make_stroke_presets.py`` rewrites them. Every op gets its own
time window in order (a drop 0.2 s or less, a stroke 1 s), so a video of a preset shows
the drops poured and the stylus travelling; a still shows the finished design.
``gesture`` is a stroke replayed as a hand drew it (``times``, format 1, revision
4) and a drop that heals. Canvas units, origin top-left, y down.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
RED, YELLOW, ORANGE = "#b0172e", "#f4d35e", "#e86a1f"
GREEN, LEAF, LIGHT_LEAF = "#2e7d32", "#3f8f3a", "#a5d27a"
PALETTE = ["#1d3557", "#b23a48", "#e9c46a", "#2a9d8f", "#f4f1de"]


def drop(center, radius, color) -> dict:
    return {"type": "drop", "center": [round(c, 1) for c in center], "radius": radius,
            "color": color}  # fmt: skip


def stroke(points, width, drag, tines=None) -> dict:
    op = {"type": "stroke", "points": [[round(x, 1), round(y, 1)] for x, y in points],
          "width": width, "drag": drag}  # fmt: skip
    if tines is not None:
        op["tines"] = [round(t, 1) for t in tines]
    return op


def timed(ops: list[dict], drops: float = 0.2) -> list[dict]:
    """Each op in its own window, one after another: drops ``drops`` s, strokes 1 s."""
    t = 0.0
    for op in ops:
        span = drops if op["type"] == "drop" else 1.0
        op["start"], op["end"] = round(t, 2), round(t + span, 2)
        t += span
    return ops


def tulip() -> dict:
    """A column of drops, one stroke up through them and two up and out (the cup
    and its three tips); a stem of drops pulled down; two leaves pulled up."""
    x0 = 160
    ops = [
        drop((x0, y), r, c)
        for y, r, c in ((170, 50, RED), (170, 38, YELLOW), (150, 40, RED), (150, 28, YELLOW),
                        (130, 26, ORANGE), (130, 14, YELLOW))
    ]  # fmt: skip
    ops.append(stroke([(x0, 200), (x0, 55)], 30, 1.4))
    for side in (-1, 1):
        ops.append(stroke([(x0 + side * 12, 160), (x0 + side * 34, 115), (x0 + side * 50, 70)],
                          26, 1.0))  # fmt: skip
    ops += [drop((x0, 232 + 16 * k), 8, GREEN) for k in range(9)]
    ops.append(stroke([(x0, 222), (x0, 380)], 16, 1.4))
    for side in (-1, 1):
        centre = (x0 + side * 34, 318 - side * 8)
        ops += [drop(centre, 22, LEAF), drop(centre, 10, LIGHT_LEAF)]
        path = [(x0 + side * 6, 360), (x0 + side * 30, 332), (x0 + side * 56, 290),
                (x0 + side * 68, 252)]  # fmt: skip
        ops.append(stroke(path, 30, 1.2))
    return {"description": "Tulip: a column of drops, one stroke up through them, two up and "
            "out; a stem and two leaves (strokes).", "canvas": [320, 400],
            "background": "#f6efe0", "ops": timed(ops)}  # fmt: skip


def heart() -> dict:
    """Concentric drops and one wide stroke straight down through them, on past
    the sheet's edge (where it ends it leaves a knot)."""
    rings = ((86, "#c2185b"), (68, "#f8bbd0"), (50, "#c2185b"), (32, "#fff1f5"), (16, "#c2185b"))
    ops = [drop((160, 175), r, c) for r, c in rings]
    ops.append(stroke([(160, 60), (160, 440)], 56, 1.0))
    return {"description": "Heart: concentric drops and one wide stroke down through them.",
            "canvas": [320, 400], "background": "#f6efe0", "ops": timed(ops)}  # fmt: skip


def spiral(cx: float, cy: float, r0: float, r1: float, turns: float, n: int = 64) -> list:
    """A spiral from radius r0 to r1, starting left of (cx, cy) moving up (its first
    normal N0 is +x, so a comb's tines sit in a row) and turning clockwise on screen."""
    out = []
    for i in range(n):
        f = i / (n - 1)
        a = math.pi + 2 * math.pi * turns * f
        r = r0 + (r1 - r0) * f
        out.append((cx + r * math.cos(a), cy + r * math.sin(a)))
    return out


def french_curl() -> dict:
    """The gel-git (a stone raked up and back), then rows of curls: each row one
    comb stroke along a spiral, its tines 80 apart across the sheet."""
    ops = [
        {"type": "scatter-drops", "center": [240.0, 160.0], "size": [576.0, 384.0],
         "count": 140, "radius": 26, "seed": 11, "colors": PALETTE},
        {"type": "rake", "point": [240.0, 160.0], "angle": 90, "alpha": 150, "falloff": 4,
         "spacing": 30, "count": 17},
        {"type": "rake", "point": [255.0, 160.0], "angle": 270, "alpha": 150, "falloff": 4,
         "spacing": 30, "count": 17},
    ]  # fmt: skip
    for j, y in enumerate((40, 120, 200, 280)):
        x0, cols = (40, 6) if j % 2 == 0 else (0, 7)
        tines = [k * 80.0 for k in range(cols)]
        ops.append(stroke(spiral(x0, y, 34, 6, 2.25), 26, 0.6, tines))
    ops[0].update(start=0, end=3)
    for k, op in enumerate(ops[1:]):
        op.update(start=3 + k, end=4 + k)
    return {"description": "French curl: the gel-git, then rows of curls (comb strokes along "
            "spirals).", "canvas": [480, 320], "background": "#f4f1de", "ops": ops}  # fmt: skip


def bird() -> dict:
    """Rows of ringed drops, then one comb stroke along a wave through them, a
    pair of tines either side of each row: each drop flies off as a bird."""
    rows, y0, amp, wavelength, x0 = (80, 160, 240), 160, 16, 160, 40
    ops = []
    for j, y in enumerate(rows):
        for k in range(6):
            x = x0 + 80 * k + (40 if j % 2 else 0)
            rings = ((26, PALETTE[0]), (18, PALETTE[2]), (9, PALETTE[1]))
            if (k + j) % 2:
                rings = ((26, PALETTE[3]), (18, PALETTE[4]), (9, PALETTE[0]))
            ops += [drop((x, y), r, c) for r, c in rings]
    path = [
        (x, y0 + amp * math.sin(2 * math.pi * (x - x0) / wavelength + math.pi / 2))
        for x in range(x0 - wavelength // 2, 521, 4)  # from a crest: N0 is +y
    ]
    tines = [r - y0 + o for r in rows for o in (-14, 14)]
    ops.append(stroke(path, 18, 1.0, tines))
    return {"description": "Birds: rows of ringed drops and one comb stroke along a wave "
            "through them.", "canvas": [480, 320], "background": "#eef3f7",
            "ops": timed(ops, 0.03)}  # fmt: skip


def gesture() -> dict:
    """Rings of drops poured in 0.9 s, then an S drawn through them by hand: slow
    into the first bend, quick across, a pause, slow out (``times``, one per point);
    a last drop pours in and heals away again."""
    ops = [drop((160, 120), r, c) for r, c in zip((70, 54, 38, 22), PALETTE, strict=False)]
    ops += [drop((160 + dx, 120), 16, PALETTE[2]) for dx in (-110, 110)]
    ops = timed(ops, 0.15)
    points, times = [], []
    for k in range(41):
        u = k / 40
        points.append((60 + 200 * u, 120 - 70 * math.sin(2 * math.pi * u)))
        pause = 0.3 if u > 0.6 else 0.0  # the hand rests at 60 % of the way
        times.append(round(1.0 + 2.0 * (3 * u * u - 2 * u * u * u) + pause, 3))
    ops.append({**stroke(points, 28, 1.2), "times": times})
    ops.append({**drop((270, 50), 20, RED), "start": 1.0, "end": 1.3, "heal": [3.4, 4.0]})
    return {"description": "A gesture: an S drawn through rings of drops as a hand drew it "
            "(stroke times), and a drop that heals away.", "canvas": [320, 240],
            "background": "#f4f1de", "ops": ops}  # fmt: skip


PRESETS = {
    "tulip": tulip,
    "heart": heart,
    "french-curl": french_curl,
    "bird": bird,
    "gesture": gesture,
}


def main() -> None:
    for name, make in PRESETS.items():
        design = make()
        doc = {"$schema": "./recipe.schema.json", "marblevideo": 1,
               "description": design.pop("description"), "antialias": "rgss", **design}  # fmt: skip
        (HERE / f"{name}.json").write_text(json.dumps(doc, indent=2) + "\n")
        print(f"wrote samples/{name}.json ({len(doc['ops'])} ops)")


if __name__ == "__main__":
    main()
