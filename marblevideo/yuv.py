"""YUV <-> RGBA for 8-bit 4:2:0 video frames, as the device converts them.

Conventions
-----------
- An *I420* frame is one C-contiguous uint8 array of shape ``(3 * h // 2, w)``
  (even ``w`` and ``h``): the ``h`` rows of Y, then U and then V, each
  ``(h/2, w/2)`` written row after row; this is PyAV's ``yuv420p`` ndarray.
- :class:`YuvMatrix` holds the colour matrix (Kr, Kb) and the range named by a
  frame's tags: BT.601 (also for an unspecified matrix, as swscale does),
  BT.709, BT.2020 (non-constant luminance), SMPTE 240M and FCC; limited range
  (Y 16..235, chroma 16..240) unless the frame is tagged full range or is a
  ``yuvj`` format. Other matrices return None and the frame goes through swscale.
- Decoding repeats each chroma sample over its 2x2 pixels; encoding takes the
  mean of the 2x2 pixels' RGB for the chroma. Values are rounded as
  ``floor(v + 0.5)`` and clamped to 0..255; alpha is 255 on decode and ignored on
  encode. The OpenCL kernels ``marble_from_i420`` and ``marble_to_i420`` compute
  the same float32 expressions; the functions below are their reference.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, cached_property

import numpy as np

# AVColorSpace -> (name, Kr, Kb); 2 is "unspecified", taken as BT.601 like swscale
_MATRICES = {
    1: ("bt709", 0.2126, 0.0722),
    2: ("bt601", 0.299, 0.114),
    4: ("fcc", 0.30, 0.11),
    5: ("bt601", 0.299, 0.114),
    6: ("bt601", 0.299, 0.114),
    7: ("smpte240m", 0.212, 0.087),
    9: ("bt2020nc", 0.2627, 0.0593),
}
FULL_RANGE = 2  # AVCOL_RANGE_JPEG
FORMATS = ("yuv420p", "yuvj420p")


@dataclass(frozen=True)
class YuvMatrix:
    """A Y'CbCr matrix and range; :meth:`to_rgb` and :meth:`to_yuv` are its affine maps."""

    name: str
    kr: float
    kb: float
    full: bool

    @staticmethod
    def of(colorspace: int | None, color_range: int | None, pix_fmt: str = "yuv420p"):
        """The matrix for a frame's tags (AVColorSpace, AVColorRange), or None if
        unsupported; one shared instance per matrix and range, so that its
        :attr:`kernel_args` are computed once, not once per frame."""
        found = _MATRICES.get(2 if colorspace is None else int(colorspace))
        if found is None:
            return None
        full = int(color_range or 0) == FULL_RANGE or pix_fmt.startswith("yuvj")
        return _shared(*found, full)

    def _scales(self) -> tuple[float, float, float]:
        """(luma offset, luma scale, chroma scale) of the 8-bit code values."""
        return (0.0, 255.0, 255.0) if self.full else (16.0, 219.0, 224.0)

    def to_yuv(self) -> np.ndarray:
        """(3, 4) float32: [Y, U, V] = M @ [R, G, B, 1], RGB and YUV in 0..255 codes."""
        kr, kb = self.kr, self.kb
        kg = 1.0 - kr - kb
        off, ys, cs = self._scales()
        luma = np.array([kr, kg, kb])
        cb = (np.array([0.0, 0.0, 1.0]) - luma) / (2.0 * (1.0 - kb))
        cr = (np.array([1.0, 0.0, 0.0]) - luma) / (2.0 * (1.0 - kr))
        m = np.zeros((3, 4))
        m[0, :3], m[0, 3] = luma * ys / 255.0, off
        m[1, :3], m[1, 3] = cb * cs / 255.0, 128.0
        m[2, :3], m[2, 3] = cr * cs / 255.0, 128.0
        return m.astype(np.float32)

    def to_rgb(self) -> np.ndarray:
        """(3, 4) float32: [R, G, B] = M @ [Y, U, V, 1], the inverse of :meth:`to_yuv`."""
        fwd = np.vstack([self.to_yuv().astype(np.float64), [0.0, 0.0, 0.0, 1.0]])
        return np.linalg.inv(fwd)[:3].astype(np.float32)

    @cached_property
    def kernel_args(self) -> tuple[np.ndarray, np.ndarray]:
        """(to_rgb, to_yuv) as 16 float32 each (row-major 3x4, then padding): the
        kernels' ``float16`` arguments, computed once per matrix."""
        return tuple(
            np.concatenate([m.ravel(), np.zeros(4, np.float32)])
            for m in (self.to_rgb(), self.to_yuv())
        )


@cache
def _shared(name: str, kr: float, kb: float, full: bool) -> YuvMatrix:
    return YuvMatrix(name, kr, kb, full)


def _affine(m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> list[np.ndarray]:
    """Each row of ``m`` applied to (a, b, c, 1) in float32, in the kernel's order."""
    return [((m[i, 0] * a + m[i, 1] * b) + m[i, 2] * c) + m[i, 3] for i in range(3)]


def _code(v: np.ndarray) -> np.ndarray:
    return np.clip(np.floor(v + np.float32(0.5)), 0, 255).astype(np.uint8)


def i420_to_rgba(planes: np.ndarray, matrix: YuvMatrix) -> np.ndarray:
    """(3h/2, w) I420 -> (h, w, 4) RGBA (reference of ``marble_from_i420``)."""
    h, w = planes.shape[0] * 2 // 3, planes.shape[1]
    y = planes[:h].astype(np.float32)
    chroma = planes[h:].reshape(2, h // 2, w // 2).astype(np.float32)
    u, v = (c.repeat(2, axis=0).repeat(2, axis=1) for c in chroma)
    rgb = _affine(matrix.to_rgb(), y, u, v)
    out = np.empty((h, w, 4), np.uint8)
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
    return np.concatenate([_code(y).ravel(), _code(u).ravel(), _code(v).ravel()]).reshape(
        3 * h // 2, w
    )
