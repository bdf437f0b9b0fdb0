"""Bilinear sampling of an input at input pixel coordinates, with the recipe's
``edges`` mode deciding what lies outside it."""

from __future__ import annotations

import numpy as np

from marblevideo.recipe.frame import EDGE_MODES
from marblevideo.reference.walk import ArrayLike, points


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
    xs, ys = points(xs, ys)
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
