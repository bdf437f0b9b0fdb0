"""Drop layouts: shorthand for a list of ``drop`` s, expanded in place when a
recipe loads (format 1, revision 2): ``rings``, ``line-drops``, ``grid-drops``,
``scatter-drops``.

A layout's fields are constants (no keyframe tracks). ``colors`` is a list of
colours used in turn (drop k takes colors[k mod len]). With ``start`` and
``end`` the window is cut into n equal consecutive windows, one per drop in
order; with only ``start``, every drop starts then. Every drop takes the
layout's ``heal``. Scatters draw from
SplitMix64 seeded with ``seed``, so the same seed gives the same drops on every
machine. Conventions as :mod:`marblevideo.ops.base` (degrees, y down).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass

from marblevideo.limits import MAX_COUNT
from marblevideo.ops.base import Param
from marblevideo.ops.gestures import Tool

Placement = list[tuple[tuple[float, float], float]]  # (centre, radius) of each drop


@dataclass(frozen=True)
class LayoutDef:
    """A layout: its parameters (constants), and ``place(fields)``, the centre and
    radius of each of its drops in order (``fields`` with defaults filled in)."""

    type: str
    help: str
    params: tuple[Param, ...]
    place: Callable[[Mapping], Placement]
    example: Mapping
    check: Callable[[Mapping, Mapping], list] | None = None
    tools: tuple[Tool, ...] = ()  # the designer's (marblevideo.ops.gestures)

    @property
    def kinds(self) -> dict[str, str]:
        return {p.name: p.kind for p in self.params}


def _constant(name: str, kind: str, help_: str, **more) -> Param:
    return Param(name, kind, help_, keyable=False, **more)


COLORS = _constant("colors", "colorList", "Colours of the drops, used in turn.")
RADIUS = _constant("radius", "positive", "Radius of each drop in canvas units.", slider="length")
COUNT = _constant("count", "count", "Number of drops.")
ANGLE = _constant(
    "angle",
    "number",
    "Rotation of the layout in degrees (clockwise on screen).",
    slider="angle",
    optional=True,
    default=0,
)


def _rot(x: float, y: float, degrees: float) -> tuple[float, float]:
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    return x * c - y * s, x * s + y * c


def _rings(f: Mapping) -> Placement:
    n, w = int(f["count"]), float(f["width"])
    centre = tuple(map(float, f["center"]))
    return [(centre, w * math.sqrt(2 * (n - k) - 1)) for k in range(n)]


def _line(f: Mapping) -> Placement:
    n, r = int(f["count"]), float(f["radius"])
    (ax, ay), (bx, by) = f["from"], f["to"]
    step = 1.0 / (n - 1) if n > 1 else 0.0
    return [((ax + (bx - ax) * k * step, ay + (by - ay) * k * step), r) for k in range(n)]


def _grid(f: Mapping) -> Placement:
    (ox, oy), (sx, sy) = f["origin"], f["spacing"]
    cols, rows = (int(v) for v in f["size"])
    out = []
    for j in range(rows):
        columns = range(cols) if j % 2 == 0 else range(cols - 1, -1, -1)  # serpentine
        for i in columns:
            dx, dy = _rot(i * sx, j * sy, float(f["angle"]))
            out.append(((ox + dx, oy + dy), float(f["radius"])))
    return out


MASK64 = (1 << 64) - 1


def splitmix64(seed: int) -> Iterator[float]:
    """Uniform numbers in [0, 1) from SplitMix64 seeded with ``seed``, as the
    contract states it (mod 2^64 arithmetic; u = (z >> 11) / 2^53)."""
    state = seed & MASK64
    while True:
        state = (state + 0x9E3779B97F4A7C15) & MASK64
        z = state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
        z ^= z >> 31
        yield (z >> 11) / float(1 << 53)


def _scatter(f: Mapping) -> Placement:
    (cx, cy), (lx, ly) = f["center"], f["size"]
    draws = splitmix64(int(f["seed"]))
    normal = f["distribution"] == "normal"
    out = []
    for _ in range(int(f["count"])):
        u1, u2 = next(draws), next(draws)
        if normal:
            g = math.sqrt(-2.0 * math.log(1.0 - u1))
            ox = g * math.cos(2 * math.pi * u2) * lx / math.sqrt(8)
            oy = g * math.sin(2 * math.pi * u2) * ly / math.sqrt(8)
        else:
            ox, oy = (u1 - 0.5) * lx, (u2 - 0.5) * ly
        dx, dy = _rot(ox, oy, float(f["angle"]))
        out.append(((cx + dx, cy + dy), float(f["radius"])))
    return out


def _check_grid(layout, fields) -> list:
    cols, rows = layout["size"]
    if cols * rows > MAX_COUNT:
        return [(["size"], f"must make at most {MAX_COUNT} drops, got {cols} x {rows}")]
    return []


RINGS = LayoutDef(
    type="rings",
    help="Concentric rings of ink: drops poured at one centre, the first outermost.",
    params=(
        _constant("center", "point", "Centre [x, y] in canvas units."),
        _constant("width", "positive", "Width of each ring in canvas units.", slider="length"),
        COUNT.but(help="Number of rings (drops)."),
        COLORS.but(help="Colours of the rings, outermost first, used in turn."),
    ),
    place=_rings,
    tools=(
        Tool(
            "centre",
            {
                "center": "a",
                "width": {"positive": {"div": ["len", 3]}},
                "count": 5,
                "colors": "inks",
            },
            label="width",
        ),
    ),
    example={
        "type": "rings",
        "center": [40, 30],
        "width": 5,
        "count": 4,
        "colors": ["#1d3557", "#e9c46a"],
    },  # fmt: skip
)

LINE_DROPS = LayoutDef(
    type="line-drops",
    help="Drops in a row from `from` to `to`, evenly spaced.",
    params=(
        _constant("from", "point", "Where the first drop falls [x, y]."),
        _constant("to", "point", "Where the last drop falls [x, y]."),
        COUNT,
        RADIUS,
        COLORS,
    ),
    place=_line,
    tools=(
        Tool(
            "line",
            {
                "from": "a",
                "to": "tip",
                "count": 8,
                "radius": {"positive": {"div": ["len", 16]}},
                "colors": "inks",
            },
            label="radius",
        ),
    ),
    example={
        "type": "line-drops",
        "from": [10, 30],
        "to": [70, 30],
        "count": 5,
        "radius": 6,
        "colors": ["#e63946", "#f1faee", "#457b9d"],
    },  # fmt: skip
)

GRID_DROPS = LayoutDef(
    type="grid-drops",
    help="Drops on a grid, row by row top to bottom, each row the other way (serpentine).",
    params=(
        _constant("origin", "point", "Where the first drop falls [x, y]."),
        _constant("spacing", "positivePair", "Distance between drops [sx, sy] in canvas units."),
        _constant("size", "countPair", "Columns and rows [cols, rows]."),
        RADIUS,
        ANGLE,
        COLORS,
    ),
    place=_grid,
    check=_check_grid,
    tools=(
        Tool(
            "line",
            {
                "origin": [{"min": ["a.0", "tip.0"]}, {"min": ["a.1", "tip.1"]}],
                "spacing": [
                    {"positive": {"or": [{"div": [{"abs": "dx"}, 4]}, {"div": ["side", 20]}]}},
                    {"positive": {"or": [{"div": [{"abs": "dy"}, 3]}, {"div": ["side", 20]}]}},
                ],
                "size": [5, 4],
                "radius": {"positive": {"div": [{"min": ["op.spacing.0", "op.spacing.1"]}, 3]}},
                "colors": "inks",
            },
            label="radius",
        ),
    ),
    example={
        "type": "grid-drops",
        "origin": [15, 12],
        "spacing": [16, 12],
        "size": [4, 3],
        "radius": 5,
        "colors": ["#2a9d8f", "#e9c46a", "#e76f51"],
    },  # fmt: skip
)

SCATTER_DROPS = LayoutDef(
    type="scatter-drops",
    help="Drops scattered at random (seeded) over a rectangle around `center`.",
    params=(
        _constant("center", "point", "Centre [x, y] of the scatter in canvas units."),
        _constant("size", "positivePair", "Width and height [Lx, Ly] of the scatter."),
        ANGLE,
        COUNT,
        RADIUS,
        _constant("seed", "seed", "Seed of the SplitMix64 stream: the same seed, the same drops."),
        _constant(
            "distribution",
            "distribution",
            "uniform (over the rectangle) or normal (around its centre).",
            optional=True,
            default="uniform",
        ),
        COLORS,
    ),
    place=_scatter,
    tools=(
        Tool(
            "centre",
            {
                "center": "a",
                "size": [
                    {"positive": {"or": [{"mul": [2, {"abs": "dx"}]}, {"div": ["side", 5]}]}},
                    {"positive": {"or": [{"mul": [2, {"abs": "dy"}]}, {"div": ["side", 5]}]}},
                ],
                "count": 24,
                "radius": {"positive": {"div": ["side", 40]}},
                "seed": "seed",
                "colors": "inks",
            },
            label="size",
        ),
    ),
    example={
        "type": "scatter-drops",
        "center": [40, 30],
        "size": [60, 40],
        "count": 12,
        "radius": 4,
        "seed": 7,
        "colors": ["#264653", "#f4a261"],
    },  # fmt: skip
)

LAYOUTS: dict[str, LayoutDef] = {d.type: d for d in (RINGS, LINE_DROPS, GRID_DROPS, SCATTER_DROPS)}


def expand(layout: Mapping) -> list[dict]:
    """The drops a valid layout (as JSON) stands for, in order, with their windows."""
    definition = LAYOUTS[layout["type"]]
    fields = {p.name: p.default for p in definition.params if p.default is not None}
    fields.update(layout)
    placed = definition.place(fields)
    colors = layout["colors"]
    start, end = layout.get("start"), layout.get("end")
    drops = []
    for k, (centre, radius) in enumerate(placed):
        drop = {"type": "drop", "center": list(centre), "radius": radius,
                "color": colors[k % len(colors)]}  # fmt: skip
        if start is not None and end is not None:
            span = (end - start) / len(placed)
            drop["start"], drop["end"] = start + k * span, start + (k + 1) * span
        elif start is not None:
            drop["start"] = start
        if "heal" in layout:
            drop["heal"] = layout["heal"]
        drops.append(drop)
    return drops
