"""The outlines of a blank-sheet design's ink, refined (:mod:`marblevideo.outputs.svg`
writes them).

Every drop and spray of a :class:`~marblevideo.recipe.frame.FrameSpec` is a circle
whose paint is carried by the *later* ops only: its boundary is sampled on the
original circle and pushed through the float64 forward maps of the later ops'
definitions (:mod:`marblevideo.ops`). The samples of every shape go through the
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

Conventions: canvas units, origin top-left, x right, y down; the tolerance is
in canvas units here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from marblevideo.ops import identity, op_def
from marblevideo.recipe.frame import FrameSpec

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
PROBED = 0.4
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
    shapes = _first_outlines(spec, tol)
    total = sum(s.theta.size for s in shapes)
    for _ in range(MAX_PASSES):
        open_edges = [np.flatnonzero(~s.done) for s in shapes]
        if not any(e.size for e in open_edges):
            break
        probes = [_probe_angles(s, edges) for s, edges in zip(shapes, open_edges, strict=True)]
        images = _images(spec, shapes, probes)
        for s, edges, theta_in, (qx, qy) in zip(shapes, open_edges, probes, images, strict=True):
            if not edges.size:
                continue
            qx, qy = qx.reshape(-1, PROBES), qy.reshape(-1, PROBES)
            ok = _straight(s, edges, qx, qy, tol)
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


def _first_outlines(spec: FrameSpec, tol: float) -> list[Outline]:
    """Every ink op's circle sampled :data:`MAX_EDGE` / 2 tolerances apart, pushed."""
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
    return shapes


def _probe_angles(s: Outline, edges: np.ndarray) -> np.ndarray:
    """The angles :data:`INSIDE` each of ``edges`` (the last edge closes at 2 pi),
    :data:`PROBES` per edge, edge after edge."""
    start = s.theta[edges]
    end = np.where(edges + 1 < s.theta.size, s.theta[(edges + 1) % s.theta.size], 2 * math.pi)
    return np.stack([start + q * (end - start) for q in INSIDE], axis=1).ravel()


def _straight(s: Outline, edges: np.ndarray, qx: np.ndarray, qy: np.ndarray, tol: float):
    """Which of ``edges`` are accepted, given their probes' images ``qx``, ``qy``
    (one row per edge): close to the chord, even in speed, short enough."""
    nxt = (edges + 1) % s.theta.size
    ax, ay, bx, by = s.x[edges], s.y[edges], s.x[nxt], s.y[nxt]
    off = np.max(
        [_segment_distance(qx[:, i], qy[:, i], ax, ay, bx, by) for i in range(PROBES)], axis=0
    )
    # the image's speed along the edge, from its eighths: a feature between the
    # probes shows as an eighth much faster than another (a stretch changing)
    px = np.column_stack([ax, qx, bx])
    py = np.column_stack([ay, qy, by])
    quarter = np.hypot(np.diff(px, axis=1), np.diff(py, axis=1))
    even = quarter.max(axis=1) <= SPEED_RATIO * quarter.min(axis=1) + REFINED * tol / 4
    return (off <= PROBED * tol) & (np.hypot(bx - ax, by - ay) <= MAX_EDGE * tol) & even
