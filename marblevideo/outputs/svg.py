"""Blank-sheet designs as resolution-independent SVG (paper, section 3.3, and beyond).

Every drop and spray of a :class:`~marblevideo.recipe.frame.FrameSpec` is a circle
whose paint is carried by the *later* ops only: its boundary is sampled on the
original circle and pushed through the float64 forward maps of the later ops'
definitions (:mod:`marblevideo.ops`; a later drop pushes earlier paint outward,
a spray does not move anything). The samples of every shape go through the
ops together, one NumPy call per op and pass.

The outlines come refined from :mod:`marblevideo.outputs.outlines`.
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

import functools
import math

import numpy as np

from marblevideo.limits import DEFAULT_TOLERANCE
from marblevideo.outputs.outlines import REFINED, VectorStats, refine_outlines
from marblevideo.recipe.frame import FrameSpec, fit

#: Share of the tolerance the written coordinates' rounding may take (the
#: simplification has the rest: SIMPLIFIED).
ROUNDED = 0.05
SIMPLIFIED = 1 - REFINED - ROUNDED
#: The simplification keeps every SPAN-th refined vertex (bounds its passes).
SPAN = 256
#: In the SVG path, every ANCHOR-th vertex is absolute, the others relative.
ANCHOR = 16


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


@functools.lru_cache(maxsize=1 << 16)  # a path's steps are mostly a few small values
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
