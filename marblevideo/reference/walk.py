"""The walk: points carried through ops by their definitions' maps
(:mod:`marblevideo.ops`), one op (:func:`forward`, :func:`inverse`,
:func:`jacobian`) or a frame's ops backwards (:func:`inverse_walk`).

Conventions: canvas units, origin top-left, x right, y down; points are
broadcastable float64 arrays (no per-point Python loop). Where the contract is
silent this module chooses, and the kernel must match: in :func:`inverse_walk`
a point that hits ink keeps the coordinates it had when it reached that ink op
(the inverses of the later ops applied, not of the ink op itself).
"""

from __future__ import annotations

import numpy as np

from marblevideo.ops import op_def
from marblevideo.recipe.frame import FrameSpec, OpState

ArrayLike = np.ndarray | float
Points = tuple[np.ndarray, np.ndarray]


def points(x: ArrayLike, y: ArrayLike) -> Points:
    """``x``, ``y`` as float64 arrays broadcast to one shape."""
    x, y = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
    return x, y


def contains(op: OpState, x: ArrayLike, y: ArrayLike) -> np.ndarray:
    """Whether the ink op ``op`` holds each point (see :mod:`marblevideo.ops.ink`).

    False everywhere for an ink op at progress 0 and for ops that are not ink.
    """
    x, y = points(x, y)
    definition = op_def(op.type)
    if not definition.ink:
        return np.zeros(x.shape, dtype=bool)
    return definition.contains(op.values, x, y)


def forward(op: OpState, x: ArrayLike, y: ArrayLike) -> Points:
    """Where paint at canvas point (x, y) moves under ``op``: P -> P'.

    For a drop this is meant for points outside the new drop (every P != C);
    see :mod:`marblevideo.ops.ink` for P = C. Spray is the identity.
    """
    x, y = points(x, y)
    return op_def(op.type).forward(op.values, x, y)


def inverse(op: OpState, x: ArrayLike, y: ArrayLike) -> Points:
    """Where the paint now at canvas point (x', y') came from under ``op``: P' -> P.

    Exact inverse of :func:`forward`. For a drop it is meant for |P' - C| >= r
    (points inside are ink and map to C). Spray is the identity.
    """
    x, y = points(x, y)
    return op_def(op.type).inverse(op.values, x, y)


def jacobian(op: OpState, x: ArrayLike, y: ArrayLike, h: ArrayLike = 1e-6) -> np.ndarray:
    """Numerical Jacobian of :func:`forward` by central differences, shape (..., 2, 2).

    ``h`` (a scalar or one per point) is relative: the step is h * max(1, |P|).
    J[..., i, j] = d out_i / d in_j.
    """
    x, y = points(x, y)
    step = h * np.maximum(1.0, np.hypot(x, y))
    fxp, fyp = forward(op, x + step, y)
    fxm, fym = forward(op, x - step, y)
    gxp, gyp = forward(op, x, y + step)
    gxm, gym = forward(op, x, y - step)
    j = np.empty(x.shape + (2, 2))
    j[..., 0, 0] = (fxp - fxm) / (2 * step)
    j[..., 1, 0] = (fyp - fym) / (2 * step)
    j[..., 0, 1] = (gxp - gxm) / (2 * step)
    j[..., 1, 1] = (gyp - gym) / (2 * step)
    return j


def inverse_walk(
    spec: FrameSpec, x: ArrayLike, y: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Walk canvas points back through ``spec.ops``, last op first.

    Returns (x0, y0, ink): ``ink`` is the index in ``spec.ops`` of the ink op
    (drop or spray of radius > 0) that holds the point, checked before that
    op's own inverse; the first one met ends the walk. ``ink`` is -1 for a
    point that reached the start, and (x0, y0) is then where it samples the
    input. A point that hit ink keeps the coordinates it had on reaching that
    op (meaningful only as a debugging aid).
    """
    x, y = points(x, y)
    x, y = x.copy(), y.copy()
    ink = np.full(x.shape, -1, dtype=np.int64)
    for k in range(len(spec.ops) - 1, -1, -1):
        op = spec.ops[k]
        definition = op_def(op.type)
        live = ink < 0
        if definition.ink:
            hit = live & definition.contains(op.values, x, y)
            ink[hit] = k
            live &= ~hit
        if not live.any():
            break
        x[live], y[live] = definition.inverse(op.values, x[live], y[live])
    return x, y, ink
