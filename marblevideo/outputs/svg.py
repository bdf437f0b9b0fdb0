"""Blank-sheet designs as resolution-independent SVG (paper, section 3.3, and beyond).

Every drop and spray of a :class:`~marblevideo.recipe.frame.FrameSpec` is a circle
whose paint is carried by the *later* ops only: its boundary is sampled on the
original circle and pushed through the float64 forward maps of the later ops'
definitions (:mod:`marblevideo.ops`; a later drop pushes earlier paint outward,
a spray does not move anything). The samples of every shape go through the
ops together, one NumPy call per op and pass.

Refinement splits an edge (two neighbouring samples) until its image is
straight: an edge is accepted only when the images of seven points inside it
(at each eighth of its angle) lie within 0.4 of its share of the tolerance
(:data:`REFINED`) of the edge's chord *segment*, the image covers each eighth
at about the same speed (no eighth :data:`SPEED_RATIO` times longer than
another: a stretch changing inside the edge), and the chord is at most
:data:`MAX_EDGE` tolerances long; otherwise the seven points become vertices.
So a feature must slip between seven samples of a short edge to be missed,
where a rule settling an edge on its midpoint alone loses thin filaments. The
first samples are spaced :data:`MAX_EDGE` / 2 tolerances apart on the original
circle; the edges then follow the later ops' stretch. Guards on passes and
vertices add a note to the stats when one trips.

Beyond the paper ("vertex count grows quickly"), each refined polygon is then
simplified by a closed-polygon Douglas-Peucker within :data:`SIMPLIFIED` of the
tolerance, and the coordinates rounded within :data:`ROUNDED` of it: the
outline written lies within the tolerance of the true image. Paths hold every
:data:`ANCHOR`-th vertex absolute and relative steps between (a third smaller
than absolute coordinates).

Shapes are written in painter's order (later ink on top) over a background
rectangle that covers the whole visible area; the canvas is the viewBox and
the output size gives width and height, so the SVG shows what the raster
renderer shows (an ink op holds the points *strictly* inside its circle after
the inverse walk: the same regions).

Conventions: canvas units, origin top-left, x right, y down (the contract's);
the tolerance is in output pixels (at the SVG's own width and height) and
converted by the canvas->output scale.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from marblevideo.limits import DEFAULT_TOLERANCE
from marblevideo.ops import identity, op_def
from marblevideo.recipe.frame import FrameSpec, fit

#: Refinement passes at most (each can quarter an edge).
MAX_PASSES = 40
#: Refined vertices over all shapes at most; refinement stops there with a note.
MAX_VERTICES = 8_000_000
#: An edge's chord is at most this many tolerances long.
MAX_EDGE = 32.0
#: Where inside an edge its image is tested (shares of its angle).
INSIDE = (0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875)
PROBES = len(INSIDE)
#: An edge whose image covers one quarter of its angle this many times faster than
#: another is split (its stretch changes inside it).
SPEED_RATIO = 2.0
#: Share of the tolerance the refined outline may be off (the rest is the
#: simplification's), and how much of it the probes may use (the curve between
#: them keeps the rest).
REFINED = 0.5
#: Share of the tolerance the written coordinates' rounding may take (the
#: simplification has the rest: SIMPLIFIED).
ROUNDED = 0.05
SIMPLIFIED = 1 - REFINED - ROUNDED
PROBED = 0.4
#: The simplification keeps every SPAN-th refined vertex (bounds its passes).
SPAN = 256
#: In the SVG path, every ANCHOR-th vertex is absolute, the others relative.
ANCHOR = 16
#: Points carried through the forward maps together (a cache-sized block).
BLOCK = 1 << 15


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


def push_forward(spec: FrameSpec, first, x: np.ndarray, y: np.ndarray):
    """Carry canvas points through the ops after ``first`` by their forward maps;
    ``first`` is an op index, or one per point (the ink op whose outline the
    point is on).

    Points go through in blocks of :data:`BLOCK` (each op's arrays stay in the
    cache), sorted by ``first`` so that the points an op moves are a prefix.
    """
    x, y = np.array(x, dtype=np.float64), np.array(y, dtype=np.float64)
    first = np.broadcast_to(np.asarray(first), x.shape).ravel()
    shape = x.shape
    x, y = x.ravel(), y.ravel()
    order = None
    if first.size > 1 and np.any(first[1:] < first[:-1]):
        order = np.argsort(first, kind="stable")
        first, x, y = first[order], x[order], y[order]
    steps = [
        (j, op_def(op.type).forward, op.values)
        for j, op in enumerate(spec.ops)
        if op_def(op.type).forward is not identity and not op_def(op.type).absent(op.values)
    ]
    for lo in range(0, x.size, BLOCK):
        hi = min(lo + BLOCK, x.size)
        owners = first[lo:hi]
        for j, forward, values in steps:
            n = lo + int(np.searchsorted(owners, j))  # points whose ink came before op j
            if n > lo:
                x[lo:n], y[lo:n] = forward(values, x[lo:n], y[lo:n])
    if order is not None:
        x[order], y[order] = x.copy(), y.copy()
    return x.reshape(shape), y.reshape(shape)


@dataclass
class Outline:
    """An ink op's outline: sample angles on its circle, their images (the
    vertices), and whether each edge (vertex i -> i + 1, the last closing) is
    accepted by the refinement."""

    op: int
    center: tuple[float, float]
    radius: float
    theta: np.ndarray
    x: np.ndarray = None
    y: np.ndarray = None
    done: np.ndarray = None

    def points(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        cx, cy = self.center
        return cx + self.radius * np.cos(theta), cy + self.radius * np.sin(theta)


def _images(spec: FrameSpec, shapes: list[Outline], thetas: list[np.ndarray]) -> list:
    """The images of angles ``thetas[i]`` on ``shapes[i]``, all pushed at once."""
    sizes = [t.size for t in thetas]
    if not sum(sizes):
        return [(np.empty(0), np.empty(0)) for _ in shapes]
    xs, ys = zip(*(s.points(t) for s, t in zip(shapes, thetas, strict=True)), strict=True)
    owner = np.repeat([s.op for s in shapes], sizes)
    x, y = push_forward(spec, owner, np.concatenate(xs), np.concatenate(ys))
    cuts = np.cumsum(sizes)[:-1]
    return list(zip(np.split(x, cuts), np.split(y, cuts), strict=True))


def _segment_distance(px, py, ax, ay, bx, by) -> np.ndarray:
    """Distance of points P to the segments AB (all arrays of one shape)."""
    ex, ey = bx - ax, by - ay
    length2 = ex * ex + ey * ey
    t = np.divide(
        (px - ax) * ex + (py - ay) * ey, length2, out=np.zeros_like(px), where=length2 > 0
    )
    t = np.clip(t, 0.0, 1.0)
    return np.hypot(px - ax - t * ex, py - ay - t * ey)


def refine_outlines(spec: FrameSpec, tol: float, stats: VectorStats) -> list[Outline]:
    """The refined outline of every ink op present, within ``tol`` canvas units."""
    shapes = []
    for k, op in enumerate(spec.ops):
        definition = op_def(op.type)
        if not definition.ink or definition.absent(op.values):
            continue
        r = float(op["radius"])
        n0 = int(min(max(64, math.ceil(2 * math.pi * r / (MAX_EDGE / 2 * tol))), 1 << 16))
        theta = np.arange(n0) * (2 * math.pi / n0)
        shapes.append(Outline(k, tuple(map(float, op["center"])), r, theta))
    for shape, (x, y) in zip(shapes, _images(spec, shapes, [s.theta for s in shapes]), strict=True):
        shape.x, shape.y, shape.done = x, y, np.zeros(shape.theta.size, dtype=bool)
    total = sum(s.theta.size for s in shapes)
    for _ in range(MAX_PASSES):
        open_edges = [np.flatnonzero(~s.done) for s in shapes]
        if not any(e.size for e in open_edges):
            break
        probes = []
        for s, edges in zip(shapes, open_edges, strict=True):
            start = s.theta[edges]
            end = np.where(
                edges + 1 < s.theta.size, s.theta[(edges + 1) % s.theta.size], 2 * math.pi
            )
            probes.append(np.stack([start + q * (end - start) for q in INSIDE], axis=1).ravel())
        images = _images(spec, shapes, probes)
        for s, edges, theta_in, (qx, qy) in zip(shapes, open_edges, probes, images, strict=True):
            if not edges.size:
                continue
            nxt = (edges + 1) % s.theta.size
            ax, ay, bx, by = s.x[edges], s.y[edges], s.x[nxt], s.y[nxt]
            qx, qy = qx.reshape(-1, PROBES), qy.reshape(-1, PROBES)
            off = np.max(
                [_segment_distance(qx[:, i], qy[:, i], ax, ay, bx, by) for i in range(PROBES)],
                axis=0,
            )
            # the image's speed along the edge, from its eighths: a feature between the
            # probes shows as an eighth much faster than another (a stretch changing)
            px = np.column_stack([ax, qx, bx])
            py = np.column_stack([ay, qy, by])
            quarter = np.hypot(np.diff(px, axis=1), np.diff(py, axis=1))
            even = quarter.max(axis=1) <= SPEED_RATIO * quarter.min(axis=1) + REFINED * tol / 4
            ok = (off <= PROBED * tol) & (np.hypot(bx - ax, by - ay) <= MAX_EDGE * tol) & even
            s.done[edges[ok]] = True
            split = edges[~ok]
            if not split.size:
                continue
            if total + PROBES * split.size > MAX_VERTICES:
                stats.capped = True
                continue
            at = np.repeat(split + 1, PROBES)
            s.theta = np.insert(s.theta, at, theta_in.reshape(-1, PROBES)[~ok].ravel())
            s.x = np.insert(s.x, at, qx[~ok].ravel())
            s.y = np.insert(s.y, at, qy[~ok].ravel())
            s.done = np.insert(s.done, at, False)
            total += PROBES * split.size
        if stats.capped:
            break
    else:
        stats.capped = any((~s.done).any() for s in shapes)
    stats.shapes = len(shapes)
    stats.refined_vertices = total
    return shapes


def simplify_closed(points: np.ndarray, tol: float) -> np.ndarray:
    """Douglas-Peucker on a closed polygon ``points`` (n, 2): the kept vertices, in
    order, such that every dropped vertex lies within ``tol`` of the kept outline."""
    return points[simplified_indices(points, tol)]


def simplified_indices(points: np.ndarray, tol: float) -> np.ndarray:
    """The indices (ascending) of the vertices :func:`simplify_closed` keeps.

    Vectorised: each pass splits every open segment (one with a vertex beyond
    ``tol``) at its farthest vertex, for all open segments at once, and looks
    only at the vertices inside open segments. Every :data:`SPAN`-th vertex is
    kept from the start, so a pass costs at most the outline and the passes are
    at most :data:`SPAN` (a tight spiral, split a turn at a time, took thousands).
    """
    n = len(points)
    if n <= 4:
        return np.arange(n)
    far = int(np.argmax(np.hypot(*(points - points[0]).T)))
    p = np.concatenate([points, points[:1]])  # closed: vertex n is vertex 0
    keep = np.zeros(n + 1, dtype=bool)
    keep[[0, far, n]] = True
    keep[::SPAN] = True
    settled = np.zeros(n + 1, dtype=bool)  # at a kept vertex: its segment is done
    while True:
        kept = np.flatnonzero(keep)
        starts, ends = kept[:-1], kept[1:]
        open_ = ~settled[starts]
        starts, ends = starts[open_], ends[open_]
        inside = ends - starts - 1
        settled[starts[inside == 0]] = True
        starts, ends, inside = starts[inside > 0], ends[inside > 0], inside[inside > 0]
        if not starts.size:
            break
        # the vertices inside the open segments, segment by segment
        first = np.cumsum(inside) - inside
        owner = np.repeat(np.arange(starts.size), inside)
        q_at = starts[owner] + 1 + np.arange(owner.size) - first[owner]
        a, b, q = p[starts[owner]], p[ends[owner]], p[q_at]
        ab = b - a
        ab2 = np.einsum("ij,ij->i", ab, ab)
        t = np.divide(
            np.einsum("ij,ij->i", q - a, ab), ab2, out=np.zeros(owner.size), where=ab2 > 0
        )
        d = np.hypot(*(q - a - np.clip(t, 0.0, 1.0)[:, None] * ab).T)
        segmax = np.maximum.reduceat(d, first)
        split = segmax > tol
        settled[starts[~split]] = True
        if not split.any():
            break
        cand = np.flatnonzero((d == segmax[owner]) & split[owner])
        _, pick = np.unique(owner[cand], return_index=True)
        keep[q_at[cand[pick]]] = True
    return np.flatnonzero(keep[:-1])


def _hex(color) -> str:
    r, g, b = (int(np.clip(math.floor(c + 0.5), 0, 255)) for c in color)
    return f"#{r:02x}{g:02x}{b:02x}"


def _fmt(v: float) -> str:
    return f"{v:g}"


def _decimal(units: int, decimals: int) -> str:
    """``units`` / 10**decimals written as briefly as SVG allows (``-.05``, ``12.3``)."""
    if not decimals:
        return str(units)
    whole, frac = divmod(abs(units), 10**decimals)
    text = f"{whole}.{frac:0{decimals}d}".rstrip("0").rstrip(".")
    if text.startswith("0."):
        text = text[1:]
    return ("-" if units < 0 and text != "0" else "") + text


def _numbers(values: list[str]) -> str:
    """Numbers joined as SVG allows: no space before a minus sign, nor before a
    fraction that follows a number with a point (``1.5.25`` is 1.5 then .25)."""
    out, prev = [], "-"
    for t in values:
        if not (t.startswith("-") or (t.startswith(".") and "." in prev)):
            out.append(" ")
        out.append(t)
        prev = t
    return "".join(out)[1:] if out and out[0] == " " else "".join(out)


def _path(points: np.ndarray, decimals: int) -> str:
    """A closed path of the vertices rounded to ``decimals``: every
    :data:`ANCHOR`-th vertex absolute, the ones between as relative steps (the
    steps of rounded values, so they add up exactly; renderers accumulate
    relative steps in fixed or single-precision point, hence the anchors)."""
    units = np.round(points * 10.0**decimals).astype(np.int64)
    parts = []
    for i in range(0, len(units), ANCHOR):
        block = units[i : i + ANCHOR]
        parts.append("M" if i == 0 else "L")
        parts.append(_numbers([_decimal(int(v), decimals) for v in block[0]]))
        if len(block) > 1:
            steps = np.diff(block, axis=0).ravel().tolist()
            parts.append("l" + _numbers([_decimal(v, decimals) for v in steps]))
    parts.append("z")
    return "".join(parts)


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
    outlines = refine_outlines(spec, tol, stats)
    # a vertex moves at most 10**-decimals / sqrt(2) when rounded
    decimals = max(0, math.ceil(-math.log10(math.sqrt(2) * ROUNDED * tol)))
    bx, by = -dx / s, -dy / s  # the visible area in canvas units, beyond the viewBox
    parts = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
        f'viewBox="0 0 {_fmt(cw)} {_fmt(ch)}">',
        f'<rect x="{_fmt(bx)}" y="{_fmt(by)}" width="{_fmt(w / s)}" height="{_fmt(h / s)}" '
        f'fill="{_hex(spec.background)}"/>',
    ]
    vertices = 0
    for outline in outlines:
        simple = simplify_closed(np.stack([outline.x, outline.y], axis=1), SIMPLIFIED * tol)
        vertices += len(simple)
        color = _hex(spec.ops[outline.op]["color"])
        parts.append(f'<path fill="{color}" d="{_path(simple, decimals)}"/>')
    parts.append("</svg>\n")
    text = "\n".join(parts)
    stats.vertices = vertices
    stats.bytes = len(text.encode())
    return text, stats


PDF_HELP = "PDF output needs cairosvg: pip install 'marblevideo[pdf]' (and the cairo library)"


def pdf_writer():
    """A function ``(svg_text, path)`` that writes the SVG as a vector PDF through
    cairosvg; MarbleError (exit 1) saying how to install it when it is missing."""
    from marblevideo.errors import MarbleError

    try:
        import cairosvg
    except (ImportError, OSError) as exc:  # OSError: cairosvg without the cairo library
        raise MarbleError(f"{PDF_HELP} ({exc})") from None

    def write(svg: str, path) -> None:
        cairosvg.svg2pdf(bytestring=svg.encode(), write_to=str(path))

    return write
