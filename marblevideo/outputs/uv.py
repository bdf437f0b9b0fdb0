"""Render a design through a UV pass: marbled textures on 3D objects that stay sharp.

A UV pass (as Blender's compositor exports it) stores per pixel the texture
coordinates of the surface seen there: R = u, G = v, both 0..1, as a 16-bit
PNG or a float EXR. We follow Blender's convention: **v = 0 is the bottom of
the texture**, so a pixel shows canvas point (u * W, (1 - v) * H) of a W x H
canvas (canvas y points down). Pixels with no surface (alpha 0 where the
pass has alpha, a non-finite u or v, or u, v outside 0..1) come out
transparent (alpha 0, colour = background).

Each subsample of the recipe's antialiasing pattern is placed in canvas space
with the pass's screen-space derivatives: C(o + d) ~= C(o) + dx * dC/dx +
dy * dC/dy, where dC/dx and dC/dy are finite differences between
neighbouring pixels (central where both neighbours are on the surface, else
one-sided, else zero; a jump over half the canvas is taken as a UV seam and
skipped the same way). The design is then evaluated *exactly* at those canvas
points (paper, section 4: the closed form replaces a texture lookup), by the
float64 walk of :mod:`marblevideo.reference`, vectorised and chunked. That is
a CPU path: about 0.55 s per million subsamples for the 32-op Figure 6 on 2 cores
(a 1024 x 1024 sphere pass, 2.7 M subsamples, in 1.5 s); UV passes
are typically 2k or less.

An input image (a recipe over a photo) is sampled as in a plain render: the
input fills the canvas.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.recipe.antialias import pattern
from marblevideo.recipe.frame import FrameSpec, geometry
from marblevideo.reference import ink_colors, shade

#: Subsample points walked at once.
CHUNK = 1 << 19
UV_EXTENSIONS = frozenset({".png", ".exr", ".tif", ".tiff"})


def read_uv(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(u, v, surface) float64/bool arrays (H, W) of a UV pass file."""
    from marblevideo.media.images import opencv  # sets OpenCV's EXR switch before cv2 loads

    cv2 = opencv()

    path = Path(path)
    if path.suffix.lower() not in UV_EXTENSIONS:
        raise UsageError(f"--uv: {path}: expected a .png, .tif or .exr UV pass")
    if not path.is_file():
        raise UsageError(f"--uv: {path}: no such file")
    if path.suffix.lower() == ".exr" and not _opencv_exr(cv2):
        data = _read_exr(path)
    else:
        try:
            data = cv2.imdecode(np.fromfile(path, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
        except cv2.error as exc:
            msg = str(exc).strip().splitlines()[-1] if str(exc).strip() else "cannot decode"
            raise MediaError(f"--uv: {path}: cannot decode ({msg})") from None
    if data is None:
        raise MediaError(f"--uv: {path}: not a readable image")
    if data.ndim != 3 or data.shape[2] < 3:
        raise UsageError(f"--uv: {path}: a UV pass needs colour channels (R = u, G = v)")
    if data.dtype == np.uint16:
        scale = 65535.0
    elif data.dtype == np.uint8:
        scale = 255.0
    elif data.dtype in (np.float32, np.float16, np.float64):
        scale = 1.0
    else:
        raise MediaError(f"--uv: {path}: unsupported sample type {data.dtype}")
    px = data.astype(np.float64) / scale
    # OpenCV gives BGR(A): R = channel 2, G = channel 1
    u, v = px[..., 2], px[..., 1]
    surface = np.isfinite(u) & np.isfinite(v)
    surface &= (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
    if px.shape[2] == 4:
        surface &= px[..., 3] > 0
    return u, v, surface


def _opencv_exr(cv2) -> bool:
    info = cv2.getBuildInformation()
    return any("OpenEXR" in line and "NO" not in line for line in info.splitlines())


def _read_exr(path: Path) -> np.ndarray:
    """An EXR as float32 BGR(A) (OpenCV's channel order), through the OpenEXR package
    (OpenCV wheels are often built without EXR)."""
    try:
        import OpenEXR
    except ImportError:
        raise UsageError(
            f"--uv: {path}: reading EXR needs the OpenEXR package (pip install OpenEXR) "
            "or an OpenCV built with OpenEXR; or export the pass as a 16-bit PNG"
        ) from None
    try:
        with OpenEXR.File(str(path)) as f:
            channels = {name: np.asarray(ch.pixels) for name, ch in f.channels().items()}
    except Exception as exc:  # the bindings raise plain exceptions
        raise MediaError(f"--uv: {path}: cannot decode EXR ({exc})") from None
    planes = {}
    for name, px in channels.items():
        if px.ndim == 3:  # a group: "RGB", "RGBA"
            planes.update({c: px[..., i] for i, c in enumerate(name)})
        else:
            planes[name.split(".")[-1]] = px
    if "R" not in planes or "G" not in planes:
        raise UsageError(f"--uv: {path}: the EXR has no R and G channels (u, v)")
    zero = np.zeros_like(planes["R"])
    order = [planes.get("B", zero), planes["G"], planes["R"]]
    if "A" in planes:
        order.append(planes["A"])
    return np.stack(order, axis=-1).astype(np.float32)


def _derivative(c: np.ndarray, ok: np.ndarray, axis: int, seam: float) -> np.ndarray:
    """Finite difference of ``c`` along ``axis`` over pixels where ``ok``: central,
    else one-sided, else 0. A jump over ``seam`` (a UV seam, where the texture
    wraps) is not a derivative and is ignored like a missing neighbour."""
    fwd = np.zeros_like(c)
    bwd = np.zeros_like(c)
    has_f = np.zeros(c.shape, bool)
    has_b = np.zeros(c.shape, bool)
    lo = [slice(None)] * 2
    hi = [slice(None)] * 2
    lo[axis], hi[axis] = slice(0, -1), slice(1, None)
    lo, hi = tuple(lo), tuple(hi)
    diff = c[hi] - c[lo]
    both = ok[hi] & ok[lo] & (np.abs(diff) <= seam)
    fwd[lo] = np.where(both, diff, 0)
    has_f[lo] = both
    bwd[hi] = np.where(both, diff, 0)
    has_b[hi] = both
    central = has_f & has_b
    return np.where(central, 0.5 * (fwd + bwd), np.where(has_f, fwd, bwd))


def render_uv(
    spec: FrameSpec,
    u: np.ndarray,
    v: np.ndarray,
    surface: np.ndarray,
    image: np.ndarray | None = None,
) -> np.ndarray:
    """The design ``spec`` seen through a UV pass: RGBA uint8 of the pass's shape;
    pixels without surface are transparent."""
    cw, ch = spec.canvas
    cx = np.where(surface, u * cw, 0.0)
    cy = np.where(surface, (1.0 - v) * ch, 0.0)
    # derivatives per column and per row; a jump over half the canvas is a UV seam
    dxx, dyx = _derivative(cx, surface, 1, cw / 2), _derivative(cy, surface, 1, ch / 2)
    dxy, dyy = _derivative(cx, surface, 0, cw / 2), _derivative(cy, surface, 0, ch / 2)
    idx = np.flatnonzero(surface.ravel())
    colors = ink_colors(spec)
    to_input = None
    if image is not None:
        size = (image.shape[1], image.shape[0])
        to_input = geometry(spec.canvas, size, size).to_input
    out = np.zeros(u.shape + (4,), np.uint8)
    out[..., :3] = np.round(np.clip(spec.background, 0, 255)).astype(np.uint8)
    flat_out = out.reshape(-1, 4)
    subs = pattern(spec.antialias)
    per = max(1, CHUNK // len(subs))
    for i0 in range(0, idx.size, per):
        sel = idx[i0 : i0 + per]
        acc = np.zeros((sel.size, 4))
        px, py = cx.ravel()[sel], cy.ravel()[sel]
        ax, ay = dxx.ravel()[sel], dyx.ravel()[sel]
        bx, by = dxy.ravel()[sel], dyy.ravel()[sel]
        for ox, oy, weight in subs:
            points = (px + ox * ax + oy * bx, py + ox * ay + oy * by)
            acc += weight * shade(spec, *points, image, to_input, colors)
        flat_out[sel] = np.clip(np.floor(acc + 0.5), 0, 255).astype(np.uint8)
    return out
