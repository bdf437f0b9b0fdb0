"""Blank-sheet designs as resolution-independent SVG (paper, section 3.3, and beyond).

Every drop and spray of a :class:`~marblevideo.recipe.frame.FrameSpec` is a circle
whose paint is carried by the *later* ops only: its boundary is sampled on the
original circle and pushed through the float64 forward maps of
the later ops' definitions (:mod:`marblevideo.ops`; a later drop pushes earlier paint outward, a
spray does not move anything). Refinement is adaptive, as in the paper: while
the images of two neighbouring samples lie farther apart than the tolerance,
a sample is inserted on the original circle at their mid-angle. An edge
whose mid-angle image already lies on its chord (within a tenth of the
tolerance) and that is at most 16 tolerances long is settled instead: the
outline is straight there (this cuts Figure 6's refined vertices ninefold).
All edges of a shape are refined at once per pass (vectorised NumPy), with
guards on passes and total vertices (a note in the stats when one trips).

Beyond the paper ("vertex count grows quickly"), every refined polygon is then
simplified by a closed-polygon Douglas-Peucker, also vectorised per pass:
every dropped vertex lies within the tolerance of the kept outline.

Shapes are written in painter's order (later ink on top) over a background
rectangle that covers the whole visible area; the canvas is the viewBox and
the output size gives width and height, so the SVG shows what the raster
renderer shows (an ink op holds the points *strictly* inside its circle after
the inverse walk: the same regions).

Conventions: canvas units, origin top-left, x right, y down (the contract's);
the tolerance is in output pixels and converted by the canvas->output scale.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from marblevideo.limits import DEFAULT_TOLERANCE
from marblevideo.ops import identity, op_def
from marblevideo.recipe.frame import FrameSpec, fit

#: Refinement passes at most (each can double a shape's vertices).
MAX_PASSES = 24
#: Refined vertices over all shapes at most; refinement stops there with a note.
MAX_VERTICES = 8_000_000
#: An edge is settled (not split further) when its mid-angle image lies within
#: FLAT * tolerance of its chord and it is at most MAX_EDGE tolerances long.
FLAT = 0.1
MAX_EDGE = 16.0


@dataclass
class VectorStats:
    """What :func:`design_svg` made: shapes, vertices before/after simplification,
    whether refinement hit a guard, and the SVG's size in bytes."""

    shapes: int = 0
    refined_vertices: int = 0
    vertices: int = 0
    capped: bool = False
    bytes: int = 0

    def summary(self) -> str:
        line = (
            f"{self.shapes} shapes, {self.vertices} vertices "
            f"(refined {self.refined_vertices}, simplified within tolerance), "
            f"{self.bytes / 1024:.1f} KiB"
        )
        if self.capped:
            line += "; note: refinement stopped at its vertex/depth limit, some edges are coarser"
        return line


def push_forward(spec: FrameSpec, first: int, x: np.ndarray, y: np.ndarray):
    """Carry canvas points through ``spec.ops[first:]`` by their forward maps."""
    for op in spec.ops[first:]:
        definition = op_def(op.type)
        if definition.forward is identity or definition.absent(op.values):
            continue
        x, y = definition.forward(op.values, x, y)
    return x, y


def _outlines(spec: FrameSpec, tol: float, stats: VectorStats) -> list[tuple[int, np.ndarray]]:
    """(op index, (n, 2) refined outline in canvas units) for every ink op present."""
    shapes = []  # per shape: [index, theta, x, y]
    for k, op in enumerate(spec.ops):
        definition = op_def(op.type)
        if not definition.ink or definition.absent(op.values):
            continue
        r = float(op["radius"])
        # start with edges about 8 tolerances long on the original circle (at least 64)
        n0 = int(min(max(64, math.ceil(2 * math.pi * r / (8 * tol))), 1 << 16))
        theta = np.arange(n0) * (2 * math.pi / n0)
        shapes.append([k, theta, *_image(spec, k, theta)])
    total = sum(s[1].size for s in shapes)
    for s in shapes:
        s.append(np.zeros(s[1].size, dtype=bool))  # edge i (vertex i -> i+1) settled
    for _ in range(MAX_PASSES):
        grew = False
        for s in shapes:
            k, theta, x, y, settled = s
            ex, ey = np.roll(x, -1) - x, np.roll(y, -1) - y
            gap = np.hypot(ex, ey)
            long = np.flatnonzero((gap > tol) & ~settled)
            if long.size == 0:
                continue
            grew = True
            nxt = np.where(long + 1 < theta.size, theta[(long + 1) % theta.size], 2 * math.pi)
            mid = 0.5 * (theta[long] + nxt)
            mx, my = _image(spec, k, mid)
            # an edge whose mid-angle image lies on its chord (within FLAT * tol) and
            # that is not too long is settled: the outline is straight there
            dev = np.abs((mx - x[long]) * ey[long] - (my - y[long]) * ex[long]) / gap[long]
            flat = (dev <= FLAT * tol) & (gap[long] <= MAX_EDGE * tol)
            settled[long[flat]] = True
            split = long[~flat]
            if split.size == 0:
                continue
            if total + split.size > MAX_VERTICES:
                stats.capped = True
                break
            s[1] = np.insert(theta, split + 1, mid[~flat])
            s[2] = np.insert(x, split + 1, mx[~flat])
            s[3] = np.insert(y, split + 1, my[~flat])
            s[4] = np.insert(settled, split + 1, False)
            total += split.size
        if not grew or stats.capped:
            break
    else:
        stats.capped = True
    stats.shapes = len(shapes)
    stats.refined_vertices = total
    return [(s[0], np.stack([s[2], s[3]], axis=1)) for s in shapes]


def _image(spec: FrameSpec, k: int, theta: np.ndarray):
    op = spec.ops[k]
    cx, cy = op["center"]
    r = float(op["radius"])
    return push_forward(spec, k + 1, cx + r * np.cos(theta), cy + r * np.sin(theta))


def simplify_closed(points: np.ndarray, tol: float) -> np.ndarray:
    """Douglas-Peucker on a closed polygon ``points`` (n, 2): the kept vertices, in
    order, such that every dropped vertex lies within ``tol`` of the kept outline.

    Vectorised: each pass splits every segment whose farthest vertex is beyond
    ``tol`` at that vertex, for all segments at once.
    """
    n = len(points)
    if n <= 4:
        return points
    far = int(np.argmax(np.hypot(*(points - points[0]).T)))
    p = np.concatenate([points, points[:1]])  # closed: vertex n is vertex 0
    keep = np.zeros(n + 1, dtype=bool)
    keep[[0, far, n]] = True
    while True:
        kept = np.flatnonzero(keep)
        seg = np.cumsum(keep)[:-1] - 1  # segment of each vertex 0..n-1 (its left end)
        a = p[kept[seg]]
        b = p[kept[seg + 1]]
        q = p[:-1]
        ab = b - a
        ab2 = np.einsum("ij,ij->i", ab, ab)
        t = np.clip(
            np.divide(np.einsum("ij,ij->i", q - a, ab), ab2, out=np.zeros(n), where=ab2 > 0),
            0.0,
            1.0,
        )
        d = np.hypot(*(q - a - t[:, None] * ab).T)
        d[keep[:-1]] = -1.0
        starts = kept[:-1]
        segmax = np.maximum.reduceat(d, starts)
        split = segmax > tol
        if not split.any():
            break
        cand = np.flatnonzero((d == segmax[seg]) & split[seg])
        _, first = np.unique(seg[cand], return_index=True)
        keep[cand[first]] = True
    return points[np.flatnonzero(keep[:-1])]


def _hex(color) -> str:
    r, g, b = (int(np.clip(math.floor(c + 0.5), 0, 255)) for c in color)
    return f"#{r:02x}{g:02x}{b:02x}"


def _fmt(v: float) -> str:
    return f"{v:g}"


def _path(points: np.ndarray, decimals: int) -> str:
    q = np.round(points, decimals)
    if decimals <= 0:
        q = q.astype(np.int64)
    flat = q.ravel().tolist()
    fmt = f"{{:.{decimals}f}}" if decimals > 0 else "{}"
    coords = [fmt.format(v) for v in flat]
    # trim trailing zeros of fixed-point numbers without touching integers
    if decimals > 0:
        coords = [c.rstrip("0").rstrip(".") if "." in c else c for c in coords]
    pairs = [f"{coords[i]},{coords[i + 1]}" for i in range(0, len(coords), 2)]
    return "M" + pairs[0] + "L" + " ".join(pairs[1:]) + "Z"


def design_svg(
    spec: FrameSpec, out_size: tuple[int, int], tolerance: float = DEFAULT_TOLERANCE
) -> tuple[str, VectorStats]:
    """The design ``spec`` as SVG text for an output of ``out_size`` = (w, h) pixels,
    outlines within ``tolerance`` output pixels. Returns (svg, stats)."""
    if not tolerance > 0:
        raise ValueError(f"tolerance must be > 0, got {tolerance}")
    w, h = out_size
    cw, ch = spec.canvas
    s, dx, dy = fit(spec.canvas, w, h)
    tol = tolerance / s  # canvas units
    stats = VectorStats()
    outlines = _outlines(spec, tol, stats)
    # coordinates rounded to a tenth of the tolerance at most
    decimals = max(0, math.ceil(-math.log10(tol / 10)))
    bx, by = -dx / s, -dy / s  # the visible area in canvas units, beyond the viewBox
    parts = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
        f'viewBox="0 0 {_fmt(cw)} {_fmt(ch)}">',
        f'<rect x="{_fmt(bx)}" y="{_fmt(by)}" width="{_fmt(w / s)}" height="{_fmt(h / s)}" '
        f'fill="{_hex(spec.background)}"/>',
    ]
    vertices = 0
    for k, outline in outlines:
        simple = simplify_closed(outline, tol)
        vertices += len(simple)
        parts.append(f'<path fill="{_hex(spec.ops[k]["color"])}" d="{_path(simple, decimals)}"/>')
    parts.append("</svg>\n")
    text = "\n".join(parts)
    stats.vertices = vertices
    stats.bytes = len(text.encode())
    return text, stats
