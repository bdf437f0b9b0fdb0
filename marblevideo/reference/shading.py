"""NumPy float64 reference renderer: the oracle the OpenCL kernel is tested against.

It follows shared/recipe-format.md literally and favours clarity over speed.
Conventions, shared with the contract and :mod:`marblevideo.recipe.frame`:

- Canvas units, origin top-left, **x right, y down**. Angles in **degrees**;
  angle 0 is +x, 90 is +y (down the screen), so a positive rotation is
  clockwise on screen.
- Pixel (i, j) covers [i, i+1] x [j, j+1]; its centre is (i + 0.5, j + 0.5),
  in output and input alike.
- Colors are floats 0..255. Images are uint8 arrays (H, W, 4) RGBA, or
  (H, W, 3) RGB (see :func:`render`).
- Every function takes arrays of points (any broadcastable shapes) and is
  vectorised; there is no per-pixel Python loop.

Each op's maps are its definition's (:mod:`marblevideo.ops`, where the choices
the contract leaves open are stated); this module walks them. Where the
contract is silent it chooses, and the kernel must match: in
:func:`inverse_walk` a point that hits ink keeps the coordinates it had when it
reached that ink op (the inverses of the later ops applied, not of the ink op
itself).
"""

from __future__ import annotations

import numpy as np

from marblevideo.ops import is_ink, op_def
from marblevideo.recipe.antialias import PATTERNS, pattern
from marblevideo.recipe.frame import EDGE_MODES, FrameSpec, Geometry, OpState

ArrayLike = np.ndarray | float
Points = tuple[np.ndarray, np.ndarray]

#: Subsample points evaluated at once by :func:`render` (bounds its memory).
CHUNK_POINTS = 1 << 20


def _points(x: ArrayLike, y: ArrayLike) -> Points:
    x, y = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
    return x, y


def contains(op: OpState, x: ArrayLike, y: ArrayLike) -> np.ndarray:
    """Whether the ink op ``op`` holds each point (see :mod:`marblevideo.ops.ink`).

    False everywhere for an ink op at progress 0 and for ops that are not ink.
    """
    x, y = _points(x, y)
    definition = op_def(op.type)
    if not definition.ink:
        return np.zeros(x.shape, dtype=bool)
    return definition.contains(op.values, x, y)


def forward(op: OpState, x: ArrayLike, y: ArrayLike) -> Points:
    """Where paint at canvas point (x, y) moves under ``op``: P -> P'.

    For a drop this is meant for points outside the new drop (every P != C);
    see :mod:`marblevideo.ops.ink` for P = C. Spray is the identity.
    """
    x, y = _points(x, y)
    return op_def(op.type).forward(op.values, x, y)


def inverse(op: OpState, x: ArrayLike, y: ArrayLike) -> Points:
    """Where the paint now at canvas point (x', y') came from under ``op``: P' -> P.

    Exact inverse of :func:`forward`. For a drop it is meant for |P' - C| >= r
    (points inside are ink and map to C). Spray is the identity.
    """
    x, y = _points(x, y)
    return op_def(op.type).inverse(op.values, x, y)


def jacobian(op: OpState, x: ArrayLike, y: ArrayLike, h: ArrayLike = 1e-6) -> np.ndarray:
    """Numerical Jacobian of :func:`forward` by central differences, shape (..., 2, 2).

    ``h`` (a scalar or one per point) is relative: the step is h * max(1, |P|).
    J[..., i, j] = d out_i / d in_j.
    """
    x, y = _points(x, y)
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
    x, y = _points(x, y)
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


def _tap(i: np.ndarray, n: int, edges: str) -> tuple[np.ndarray, np.ndarray | None]:
    """Map integer tap indices into 0..n-1 by the edge mode; for ``background`` also
    return which taps were inside."""
    if edges == "clamp":
        return np.clip(i, 0, n - 1), None
    if edges == "repeat":
        return np.mod(i, n), None  # numpy's integer mod is non-negative for n > 0
    if edges == "mirror":
        m = np.mod(i, 2 * n)
        return np.where(m < n, m, 2 * n - 1 - m), None
    if edges == "background":
        return np.clip(i, 0, n - 1), (i >= 0) & (i < n)
    raise ValueError(f"unknown edges mode {edges!r}; expected one of {', '.join(EDGE_MODES)}")


def sample_bilinear(
    image: np.ndarray,
    xs: ArrayLike,
    ys: ArrayLike,
    edges: str,
    background_rgb: tuple[float, float, float],
) -> np.ndarray:
    """Bilinear samples of an RGBA uint8 ``image`` (H, W, 4) at input pixel coordinates.

    Pixel i covers [i, i+1], centre i + 0.5; interpolation runs between centres:
    fx = x - 0.5, x0 = floor(fx), wx = fx - x0, taps x0 and x0 + 1 (y likewise),
    value = (1-wy)((1-wx) p00 + wx p10) + wy((1-wx) p01 + wx p11).
    Each tap index is mapped by ``edges``: ``clamp`` to 0..W-1, ``repeat``
    i mod W, ``mirror`` m = i mod 2W then m if m < W else 2W-1-m, ``background``
    a tap outside the image is ``background_rgb`` with alpha 255.
    Coordinates must be finite. Returns float64 RGBA 0..255 of shape xs.shape + (4,).
    """
    xs, ys = _points(xs, ys)
    h, w = image.shape[:2]
    fx, fy = xs - 0.5, ys - 0.5
    x0f, y0f = np.floor(fx), np.floor(fy)
    wx, wy = (fx - x0f)[..., None], (fy - y0f)[..., None]
    x0, y0 = x0f.astype(np.int64), y0f.astype(np.int64)
    bg = np.array([*background_rgb, 255.0])

    def tap(ix: np.ndarray, iy: np.ndarray) -> np.ndarray:
        jx, inside_x = _tap(ix, w, edges)
        jy, inside_y = _tap(iy, h, edges)
        p = image[jy, jx].astype(np.float64)
        if inside_x is not None:
            p = np.where((inside_x & inside_y)[..., None], p, bg)
        return p

    p00, p10 = tap(x0, y0), tap(x0 + 1, y0)
    p01, p11 = tap(x0, y0 + 1), tap(x0 + 1, y0 + 1)
    return (1 - wy) * ((1 - wx) * p00 + wx * p10) + wy * ((1 - wx) * p01 + wx * p11)


def _as_rgba(image: np.ndarray) -> np.ndarray:
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] not in (3, 4):
        raise ValueError(
            f"image must be uint8 of shape (H, W, 3) or (H, W, 4), got {image.dtype} {image.shape}"
        )
    if image.shape[2] == 4:
        return image
    alpha = np.full(image.shape[:2] + (1,), 255, dtype=np.uint8)
    return np.concatenate([image, alpha], axis=2)


def ink_colors(spec: FrameSpec) -> np.ndarray:
    """(n ops, 4) float64: each ink op's colour with alpha 255, zeros for other ops."""
    rows = [(*op["color"], 255.0) if is_ink(op.type) else (0.0,) * 4 for op in spec.ops]
    return np.array(rows, dtype=np.float64).reshape(-1, 4)


def shade(
    spec: FrameSpec,
    cx: np.ndarray,
    cy: np.ndarray,
    image: np.ndarray | None = None,
    to_input: tuple[float, float, float, float] | None = None,
    colors: np.ndarray | None = None,
) -> np.ndarray:
    """The colours of canvas points (cx, cy): float64 RGBA 0..255 of shape
    cx.shape + (4,). A point the :func:`inverse_walk` ends on ink takes that op's
    colour; one that reaches the start takes ``spec.background`` on a blank
    sheet (``image`` None), else the :func:`sample_bilinear` of the RGBA
    ``image`` at input pixel coordinates c * to_input[:2] + to_input[2:] with
    ``spec.edges``. Ink and background have alpha 255. ``colors``: the
    :func:`ink_colors` of ``spec``, when the caller has them."""
    px, py, ink = inverse_walk(spec, cx, cy)
    colors = ink_colors(spec) if colors is None else colors
    value = np.empty(px.shape + (4,))
    hit = ink >= 0
    value[hit] = colors[ink[hit]]
    miss = ~hit
    if image is None:
        value[miss] = np.array([*spec.background, 255.0])
    else:
        kx, ky, tx, ty = to_input
        value[miss] = sample_bilinear(
            image, px[miss] * kx + tx, py[miss] * ky + ty, spec.edges, spec.background
        )
    return value


def render(spec: FrameSpec, geom: Geometry, image: np.ndarray | None = None) -> np.ndarray:
    """Render one frame: uint8 array (geom.out_h, geom.out_w, 4) RGBA.

    For each output pixel (i, j) and subsample (dx, dy, weight) of
    ``pattern(spec.antialias)``: output point o = (i + 0.5 + dx, j + 0.5 + dy),
    canvas point c = o * to_canvas[:2] + to_canvas[2:] per axis, then
    :func:`shade` (the walk, then ink, the input or the background). The pixel
    is the weighted sum of its subsamples, rounded as floor(v + 0.5) and
    clipped to 0..255.

    ``image`` is uint8 (H, W, 4) RGBA, or (H, W, 3) RGB: then alpha 255 is added
    for sampling and the result is (out_h, out_w, 3) RGB.
    """
    if spec.antialias not in PATTERNS:
        raise ValueError(f"unknown antialias pattern {spec.antialias!r}")
    if spec.edges not in EDGE_MODES:
        raise ValueError(f"unknown edges mode {spec.edges!r}")
    rgba = None if image is None else _as_rgba(image)
    subsamples = pattern(spec.antialias)
    colors = ink_colors(spec)
    kx, ky, tx, ty = geom.to_canvas
    out_w, out_h = geom.out_w, geom.out_h
    out = np.empty((out_h, out_w, 4), dtype=np.uint8)
    rows = max(1, CHUNK_POINTS // max(1, out_w * len(subsamples)))
    ox = np.arange(out_w, dtype=np.float64) + 0.5
    for j0 in range(0, out_h, rows):
        oy = np.arange(j0, min(out_h, j0 + rows), dtype=np.float64) + 0.5
        acc = np.zeros((oy.size, out_w, 4))
        for dx, dy, weight in subsamples:
            cx = (ox[None, :] + dx) * kx + tx
            cy = (oy[:, None] + dy) * ky + ty
            acc += weight * shade(spec, cx, cy, rgba, geom.to_input, colors)
        out[j0 : j0 + oy.size] = np.clip(np.floor(acc + 0.5), 0, 255).astype(np.uint8)
    if image is not None and image.shape[2] == 3:
        return out[..., :3].copy()
    return out
