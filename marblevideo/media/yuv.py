"""YUV <-> RGBA for 8-bit 4:2:0 video frames, as the device converts them.

Conventions
-----------
- An *I420* frame is one C-contiguous uint8 array of shape ``(3 * h // 2, w)``
  (even ``w`` and ``h``): the ``h`` rows of Y, then U and then V, each
  ``(h/2, w/2)`` written row after row; this is PyAV's ``yuv420p`` ndarray.
  A frame may also travel as its *planes* ``(y, u, v)``: 2-D uint8 arrays of
  ``(h, w)``, ``(h/2, w/2)`` and ``(h/2, w/2)`` whose rows may be padded (the
  views of a decoded frame's own buffers, which save a copy per frame);
  :func:`split_i420` takes either form, :func:`packed_i420` makes the first.
- :class:`YuvMatrix` holds the colour matrix (Kr, Kb) and the range named by a
  frame's tags: BT.601 (also for an unspecified matrix, as swscale does),
  BT.709, BT.2020 (non-constant luminance), SMPTE 240M and FCC; limited range
  (Y 16..235, chroma 16..240) unless the frame is tagged full range or is a
  ``yuvj`` format. Other matrices return None and the frame goes through swscale.
- Decoding repeats each chroma sample over its 2x2 pixels; encoding takes the
  mean of the 2x2 pixels' RGB for the chroma. Values are rounded as
  ``floor(v + 0.5)`` and clamped to 0..255; alpha is 255 on decode and ignored on
  encode. The OpenCL kernels ``marble_from_i420`` and ``marble_to_i420`` compute
  the same float32 expressions; :mod:`marblevideo.reference.yuv` is their
  reference.
- *Planar* rendering (:func:`marblevideo.reference.yuv.render_planes`, used when
  a frame's input and output share one matrix) warps the planes themselves:
  luma at full resolution, both chroma planes at half, where chroma sample (i, j) covers
  luma pixels 2i..2i+1 x 2j..2j+1 (centred, as the 2x2 conventions above), so
  its centre is at luma (2i + 1, 2j + 1) (:mod:`marblevideo.recipe.geometry`). Ink and
  background colours become their 8-bit codes
  (:func:`marblevideo.recipe.geometry.coded_spec`). The luma equals the RGBA path's
  up to that path's rounding and clamping of the intermediate RGB; the
  chroma is sampled at chroma resolution instead of being the mean of four
  RGBA pixels, as ffmpeg's filters do on yuv420p.
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


def split_i420(frame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The planes (y, u, v) of an I420 frame given packed or as planes (views, no
    copy); ValueError for a frame that is neither, or odd-sized."""
    if isinstance(frame, np.ndarray):
        if frame.dtype != np.uint8 or frame.ndim != 2 or frame.shape[0] % 3:
            raise ValueError(
                f"I420 frames must be (3h/2, w) uint8 with even w and h, got {frame.shape}"
            )
        h, w = frame.shape[0] * 2 // 3, frame.shape[1]
        if h % 2 or w % 2:
            raise ValueError(f"I420 frames need even sizes, got {w}x{h}")
        frame = np.ascontiguousarray(frame)
        chroma = frame[h:].reshape(2, h // 2, w // 2)
        return frame[:h], chroma[0], chroma[1]
    try:
        y, u, v = frame
    except (TypeError, ValueError):
        raise ValueError("I420 frames are one (3h/2, w) array or planes (y, u, v)") from None
    h, w = getattr(y, "shape", (1, 1))[:2]
    half = (h // 2, w // 2)
    for plane, shape in ((y, (h, w)), (u, half), (v, half)):
        if not isinstance(plane, np.ndarray) or plane.dtype != np.uint8 or plane.shape != shape:
            raise ValueError(
                f"I420 planes must be uint8 of {w}x{h}, {w // 2}x{h // 2}, {w // 2}x{h // 2}"
            )
        if plane.strides[1] != 1:
            raise ValueError("I420 planes need contiguous rows")
    if h % 2 or w % 2:
        raise ValueError(f"I420 frames need even sizes, got {w}x{h}")
    return y, u, v


def packed_i420(frame) -> np.ndarray:
    """An I420 frame as one (3h/2, w) array: ``frame`` itself when packed, else its
    planes copied row after row."""
    if isinstance(frame, np.ndarray):
        split_i420(frame)
        return np.ascontiguousarray(frame)
    y, u, v = split_i420(frame)
    return np.concatenate([y.ravel(), u.ravel(), v.ravel()]).reshape(-1, y.shape[1])
