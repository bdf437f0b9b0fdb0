"""Reference of the device's I420 work (float32, as the kernels compute it):
conversions between I420 and RGBA (``marble_from_i420``, ``marble_to_i420``)
and planar rendering (``marble_plane``). Conventions: :mod:`marblevideo.media.yuv`."""

from __future__ import annotations

import numpy as np

from marblevideo.media.yuv import YuvMatrix, packed_i420, split_i420
from marblevideo.recipe.frame import FrameSpec, Geometry
from marblevideo.recipe.geometry import chroma_geometry, coded_spec
from marblevideo.reference.shading import render as reference_render


def _affine(m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> list[np.ndarray]:
    """Each row of ``m`` applied to (a, b, c, 1) in float32, in the kernel's order."""
    return [((m[i, 0] * a + m[i, 1] * b) + m[i, 2] * c) + m[i, 3] for i in range(3)]


def _code(v: np.ndarray) -> np.ndarray:
    return np.clip(np.floor(v + np.float32(0.5)), 0, 255).astype(np.uint8)


def i420_to_rgba(planes, matrix: YuvMatrix) -> np.ndarray:
    """I420 (packed or planes) -> (h, w, 4) RGBA (reference of ``marble_from_i420``)."""
    y, u, v = (p.astype(np.float32) for p in split_i420(planes))
    u, v = (c.repeat(2, axis=0).repeat(2, axis=1) for c in (u, v))
    rgb = _affine(matrix.to_rgb(), y, u, v)
    out = np.empty((*y.shape, 4), np.uint8)
    for k in range(3):
        out[..., k] = _code(rgb[k])
    out[..., 3] = 255
    return out


def rgba_to_i420(rgba: np.ndarray, matrix: YuvMatrix) -> np.ndarray:
    """(h, w, 4) RGBA, even sizes -> (3h/2, w) I420 (reference of ``marble_to_i420``)."""
    h, w = rgba.shape[:2]
    if h % 2 or w % 2:
        raise ValueError(f"I420 needs even sizes, got {w}x{h}")
    r, g, b = (rgba[..., k].astype(np.float32) for k in range(3))
    m = matrix.to_yuv()
    y = _affine(m, r, g, b)[0]

    def mean(c: np.ndarray) -> np.ndarray:
        rows = c[0::2] + c[1::2]
        return (rows[:, 0::2] + rows[:, 1::2]) * np.float32(0.25)

    _, u, v = _affine(m, mean(r), mean(g), mean(b))
    return packed_i420((_code(y), _code(u), _code(v)))


def render_planes(
    spec: FrameSpec, geom: Geometry, planes, matrix: YuvMatrix, render=reference_render
) -> np.ndarray:
    """Reference of planar rendering: the I420 ``planes`` (colours in ``matrix``)
    marbled by ``spec`` at ``geom`` (even output), as I420 in the same matrix.

    Each plane is rendered by ``render`` (:func:`marblevideo.reference.render`,
    or a stand-in with its signature) as one channel of an RGBA image, with
    :func:`coded_spec`'s colours: luma with ``geom``, chroma with
    :func:`chroma_geometry`."""
    if geom.out_w % 2 or geom.out_h % 2:
        raise ValueError(f"I420 needs even sizes, got {geom.out_w}x{geom.out_h}")
    coded = coded_spec(spec, matrix)
    y, u, v = split_i420(planes)
    opaque = np.full(y.shape, 255, np.uint8)
    luma = render(coded, geom, np.dstack([y, y, y, opaque]))
    half = opaque[: u.shape[0], : u.shape[1]]
    chroma = render(coded, chroma_geometry(geom), np.dstack([u, u, v, half]))
    codes = (luma[..., 0], chroma[..., 1], chroma[..., 2])
    return packed_i420(tuple(np.ascontiguousarray(c) for c in codes))
