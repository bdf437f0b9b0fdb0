"""What a part of a render renders: a band of output rows, the chroma planes of an
I420 render, and a :class:`~marblevideo.recipe.frame.FrameSpec`'s colours as the
8-bit codes those planes hold.

A band of rows j0..j1 of a w x h render is itself a render of w x (j1 - j0)
pixels whose output->canvas map is the full one shifted by j0 rows
(to_canvas[3] + j0 * to_canvas[1]); the kernel needs no change. The closed
form makes every band exact: it is the same function of the same canvas
points, up to the float32 rounding of the shifted offset (a last-bit
difference at a few boundary subsamples at most).

*Planar* rendering (:func:`marblevideo.reference.yuv.render_planes`) warps the
planes of an I420 frame themselves: luma at full resolution, both chroma planes at
half, where chroma sample (i, j) covers luma pixels 2i..2i+1 x 2j..2j+1, so its
centre is at luma (2i + 1, 2j + 1) (:func:`chroma_geometry`). Ink and background
colours become the matrix's codes (:func:`coded_spec`; the matrix conventions are
:mod:`marblevideo.media.yuv`'s).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import replace
from functools import cache

import numpy as np

from marblevideo.media.yuv import YuvMatrix
from marblevideo.ops import is_ink
from marblevideo.recipe.frame import FrameSpec, Geometry, OpState


def band_geometry(geom: Geometry, y0: int, rows: int) -> Geometry:
    """The geometry of output rows y0..y0+rows of ``geom``."""
    kx, ky, tx, ty = geom.to_canvas
    return Geometry(geom.out_w, rows, (kx, ky, tx, ty + y0 * ky), geom.to_input)


def bands(
    render: Callable[[Geometry], np.ndarray], geom: Geometry, rows: int
) -> Iterator[tuple[int, np.ndarray]]:
    """Yield (y0, band) for the whole output, ``render`` called once per band of
    ``rows`` rows (the last may be shorter)."""
    for y0 in range(0, geom.out_h, rows):
        n = min(rows, geom.out_h - y0)
        yield y0, render(band_geometry(geom, y0, n))


def chroma_geometry(geom: Geometry) -> Geometry:
    """The maps of a render's chroma planes (half the size of ``geom``'s even
    output, over an input's half-size chroma planes)."""
    kx, ky, tx, ty = geom.to_canvas
    sx, sy, ox, oy = geom.to_input
    return Geometry(
        geom.out_w // 2,
        geom.out_h // 2,
        (2.0 * kx, 2.0 * ky, tx, ty),
        (sx / 2.0, sy / 2.0, ox / 2.0, oy / 2.0),
    )


@cache
def _codes(matrix: YuvMatrix, rgb: tuple[float, ...]) -> tuple[float, float, float]:
    m = matrix.to_yuv().astype(np.float64)
    yuv = m[:, :3] @ np.asarray(rgb, np.float64) + m[:, 3]
    return tuple(float(v) for v in np.clip(np.floor(yuv + 0.5), 0.0, 255.0))


def coded_spec(spec: FrameSpec, matrix: YuvMatrix) -> FrameSpec:
    """``spec`` with every ink colour and the background as ``matrix``'s 8-bit
    codes (Y, Cb, Cr) in place of (r, g, b): what planar rendering blends."""
    ops = tuple(
        OpState(op.type, {**op.values, "color": _codes(matrix, tuple(op["color"]))})
        if is_ink(op.type)
        else op
        for op in spec.ops
    )
    return replace(spec, ops=ops, background=_codes(matrix, tuple(spec.background)))
