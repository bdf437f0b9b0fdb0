"""NumPy float64 reference renderer: the oracle the OpenCL kernel is tested against.

It follows docs/recipe-format.md literally and favours clarity over speed.
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
the contract leaves open are stated), walked by :mod:`.walk`; inputs are
sampled by :mod:`.sampling`; this module shades points and renders frames.
"""

from __future__ import annotations

import numpy as np

from marblevideo.ops import is_ink
from marblevideo.recipe.antialias import PATTERNS, pattern
from marblevideo.recipe.frame import EDGE_MODES, FrameSpec, Geometry
from marblevideo.reference.sampling import sample_bilinear
from marblevideo.reference.walk import inverse_walk

#: Subsample points evaluated at once by :func:`render` (bounds its memory).
CHUNK_POINTS = 1 << 20


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
