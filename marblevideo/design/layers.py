"""The designer's layers of a gesture on op k (``POST /api/layers``): the exact
picture of the ops below k and where the ops above k send every pixel, so that
the page can warp the picture by op k alone while a hand moves it (warp.js).

The *above map* of a render of ``w`` x ``h`` device pixels is float32 (h, w, 4):
per pixel (qx, qy, 0, 1), the canvas point that the inverse walk of the ops
above k leaves its centre at (where op k's inverse continues), or (r, g, b, -1)
where that walk ends on ink (an op above paints the pixel: its colour, 0..1 as
a shader's). It
is walked on the device by the renderer's own kernel ``marble_centres``
(kernels/adaptive.cl: one walk per pixel centre, the end point in canvas units
through an identity canvas -> input map), so it agrees with the exact render's
walk in float32; one sample per pixel, no antialiasing (the warp shades at the
pixel centre too).

The answer's bytes: four little-endian uint32 (w, h, k, whether an above map
follows), the base as RGBA (h, w, 4) uint8, then the above map's float32s.
"""

from __future__ import annotations

import struct

import numpy as np

#: The answer's header: w, h, k, whether the above map follows.
HEADER = struct.Struct("<IIII")


def above_map(renderer, spec, geom) -> np.ndarray:
    """Where the ops of ``spec`` send each pixel centre of ``geom``'s output, as
    the module says: float32 (h, w, 4) (``renderer``: an OpenCL Renderer)."""
    from marblevideo.opencl.program import Structure, pack_params
    from marblevideo.opencl.queue import float4
    from marblevideo.reference import ink_colors

    w, h = geom.out_w, geom.out_h
    queue = renderer.device_queue
    built = renderer.programs.get(Structure.of(spec, True))  # HAS_INPUT: end points kept
    lanes = renderer.lanes
    gstride = -(-w // lanes) * lanes
    with renderer.errors():
        uploads: list = []
        pbuf, lbuf = queue.put_params(pack_params(spec), uploads)
        inkmap = queue.buffer("above_ink", gstride * h * 4)
        sx = queue.buffer("above_x", gstride * h * 4)
        sy = queue.buffer("above_y", gstride * h * 4)
        kx, ky, tx, ty = geom.to_canvas
        # marble_centres walks grid point (i, j) from output (i - 1/2, j - 1/2):
        # shifted by one pixel, point (i, j) is pixel (i, j)'s centre
        gc = float4([kx, ky, tx + kx, ty + ky])
        k = built.kernels["marble_centres"]
        k.set_args(inkmap, sx, sy, np.int32(gstride), np.int32(h), pbuf, gc,
                   float4([1, 1, 0, 0]), lbuf)  # fmt: skip
        queue.launch(k, gstride // lanes * -(-h // built.chains))
        ink = queue.read(np.empty((h, gstride), np.int32), inkmap)[:, :w]
        qx = queue.read(np.empty((h, gstride), np.float32), sx)[:, :w]
        qy = queue.read(np.empty((h, gstride), np.float32), sy)[:, :w]
    out = np.zeros((h, w, 4), np.float32)
    out[..., 0], out[..., 1], out[..., 3] = qx, qy, 1.0
    hit = ink >= 0
    if hit.any():
        colors = ink_colors(spec).astype(np.float32)
        out[hit, :3] = colors[ink[hit], :3] / 255.0
        out[hit, 3] = -1.0
    return out


def layers_answer(base: np.ndarray, k: int, above: np.ndarray | None) -> bytes:
    """The bytes of ``POST /api/layers``'s answer (see the module)."""
    h, w = base.shape[:2]
    head = HEADER.pack(w, h, k, 0 if above is None else 1)
    tail = b"" if above is None else np.ascontiguousarray(above, np.float32).tobytes()
    return head + np.ascontiguousarray(base).tobytes() + tail


def parse_view(text: str) -> tuple[float, float, float, float]:
    """``view=x,y,w,h`` (canvas units, w and h > 0); ValueError in one line."""
    try:
        parts = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise ValueError(f"view: expected x,y,w,h in canvas units, got {text!r}") from None
    if len(parts) != 4 or not all(np.isfinite(parts)) or parts[2] <= 0 or parts[3] <= 0:
        raise ValueError(f"view: expected x,y,w,h (finite, w and h > 0), got {text!r}")
    return parts
