"""Still images in and out (PNG, JPEG, TIFF, WebP), through OpenCV.

Arrays are RGBA uint8 (H, W, 4), rows top to bottom. Alpha is kept where the
input has it and the output format can hold it (PNG, TIFF, WebP); JPEG drops
it. 16-bit inputs are reduced to 8 bits. Inputs larger than
:data:`MAX_PIXELS` are refused from their header, before any pixel is decoded.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.limits import MAX_PIXELS
from marblevideo.media.formats import IMAGE_EXTENSIONS
from marblevideo.media.inputs import Input, check_input
from marblevideo.media.tiled import png_bytes

ALPHA_EXTENSIONS = frozenset({".png", ".tif", ".tiff", ".webp"})
#: PNGs of at most this many pixels are encoded without OpenCV: its import (about
#: 0.04 s) costs more than its faster encoder saves there (on a noisy 1080p frame,
#: 0.06 s against zlib's 0.19 s; on a marbled design zlib is the faster).
SMALL_PNG = 512 * 512
#: Largest input image accepted, in pixels (about 16k x 16k).

os.environ.setdefault("OPENCV_IO_MAX_IMAGE_PIXELS", str(MAX_PIXELS))
os.environ.setdefault("OPENCV_IO_ENABLE_OPENEXR", "1")  # UV passes (marblevideo.outputs.uv)
# OpenCV's own warnings (e.g. libtiff's about extra samples) are not ours to print:
# errors reach the user as one line each, through MediaError.
os.environ.setdefault("OPENCV_LOG_LEVEL", "ERROR")


def opencv():
    """The cv2 module, imported on first use after the settings above (which it
    reads then); the video path never loads it."""
    import cv2

    return cv2


def read_image(path: str | os.PathLike | Input) -> tuple[np.ndarray, bool]:
    """(RGBA uint8 array, whether the file had alpha), of a file or of a still
    :class:`~marblevideo.media.inputs.Input` (its file checked once, or the
    bytes it read from standard input)."""
    if isinstance(path, Input):
        if path.data is not None:
            return decode_image(path.data, "-")
        path = path.checked().path
    else:
        path = check_input(path, "an image")
    try:
        data = np.fromfile(path, dtype=np.uint8)
    except OSError as exc:
        raise MediaError(f"{path}: cannot read: {exc.strerror}") from None
    return decode_image(data, path)


def decode_image(data: bytes | np.ndarray, name: str | os.PathLike) -> tuple[np.ndarray, bool]:
    """An encoded still (PNG, JPEG, TIFF, WebP bytes) as (RGBA uint8 array, whether
    it had alpha); ``name`` names it in messages."""
    cv2 = opencv()
    try:
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
    except cv2.error as exc:
        if "MAX_IMAGE_PIXELS" in str(exc):  # refused from the header, nothing allocated
            raise MediaError(f"{name}: image is over the limit of {MAX_PIXELS} pixels") from None
        msg = str(exc).strip().splitlines()[-1] if str(exc).strip() else "cannot decode"
        raise MediaError(f"{name}: cannot decode image ({msg})") from None
    if image is None:
        raise MediaError(f"{name}: not a readable image (or over {MAX_PIXELS} pixels)")
    if image.dtype == np.uint16:
        image = (image >> 8).astype(np.uint8)
    elif image.dtype != np.uint8:
        raise MediaError(f"{name}: unsupported sample type {image.dtype}; use 8 or 16 bits")
    if image.ndim == 2:
        return cv2.cvtColor(image, cv2.COLOR_GRAY2RGBA), False
    if image.shape[2] == 4:
        return cv2.cvtColor(image, cv2.COLOR_BGRA2RGBA), True
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGBA), False


def encode_image(
    rgba: np.ndarray, ext: str, alpha: bool = True, name: str | os.PathLike = "image"
) -> bytes:
    """``rgba`` encoded as the still format of extension ``ext``; alpha only when
    asked and the format holds it. ``name`` names it in messages. A PNG of at
    most :data:`SMALL_PNG` pixels is written by
    :func:`~marblevideo.media.tiled.png_bytes`, without OpenCV; the rest by OpenCV."""
    ext = ext.lower()
    if ext not in IMAGE_EXTENSIONS:
        raise UsageError(f"{name}: unknown image extension {ext!r}")
    small = rgba.shape[0] * rgba.shape[1] <= SMALL_PNG
    if ext == ".png" and small and rgba.shape[2:] == (4,) and rgba.dtype == np.uint8:
        return png_bytes(rgba, 4 if alpha else 3)
    cv2 = opencv()
    if alpha and ext in ALPHA_EXTENSIONS:
        pixels = cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGRA)
    else:
        pixels = cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGR)
    params = [cv2.IMWRITE_JPEG_QUALITY, 95] if ext in (".jpg", ".jpeg") else []
    if ext == ".webp":
        params = [cv2.IMWRITE_WEBP_QUALITY, 101 if alpha else 95]
    ok, encoded = cv2.imencode(ext, pixels, params)
    if not ok:
        raise MediaError(f"{name}: cannot encode as {ext}")
    return encoded.tobytes()


def write_image(
    path: str | os.PathLike,
    rgba: np.ndarray,
    alpha: bool = True,
    fmt: str | None = None,
    name: str | os.PathLike | None = None,
) -> None:
    """Write ``rgba``; alpha only when asked and the format holds it.
    ``fmt`` is the extension deciding the format (default: the path's); ``name``
    the file named in messages (default: ``path``; the target of a temporary file)."""
    path = Path(path)
    data = encode_image(rgba, fmt or path.suffix, alpha, name or path)
    try:
        with open(path, "wb") as f:  # not ndarray.tofile: its errors carry no errno
            f.write(data)
    except OSError as exc:
        raise MediaError(f"{name or path}: cannot write: {exc.strerror or exc}") from None
