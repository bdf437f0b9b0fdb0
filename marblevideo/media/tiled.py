"""Outputs larger than memory: render in bands of rows, write them as they come.

A band of rows is itself a render (:func:`marblevideo.recipe.geometry.bands`).

Bands go straight to a streaming writer: :class:`PngStream` (pure Python,
zlib + struct: IHDR, one IDAT chunk per band, IEND; rows use PNG's "Up"
filter) or tifffile (deflate strips, encoded here). Memory stays about
two bands (64 MiB each by default) whatever the output size.
"""

from __future__ import annotations

import importlib.util
import io
import os
import struct
import zlib
from collections.abc import Iterator
from typing import BinaryIO

import numpy as np

from marblevideo.errors import UsageError
from marblevideo.limits import MAX_ONE_PIECE, WEBP_MAX_SIDE

#: Pixels per band (about 64 MiB of RGBA); ``MARBLEVIDEO_BAND_PIXELS`` sets another
#: (the tests' way to make small outputs take the banded path).
BAND_PIXELS = int(os.environ.get("MARBLEVIDEO_BAND_PIXELS", 16 << 20))
#: Outputs with more pixels than this (four bands: 64 Mpixel) are rendered in
#: bands (PNG and TIFF).
TILED_ABOVE = 4 * BAND_PIXELS
STREAM_EXTENSIONS = frozenset({".png", ".tif", ".tiff"})


def can_stream(fmt: str) -> bool:
    """Whether outputs of extension ``fmt`` can be written band by band here
    (TIFF needs the optional tifffile package)."""
    if fmt == ".png":
        return True
    if fmt not in STREAM_EXTENSIONS:
        return False
    return importlib.util.find_spec("tifffile") is not None  # found, not imported


def check_still_size(
    name: str | os.PathLike, fmt: str, size: tuple[int, int], stream: bool = True
) -> None:
    """UsageError, before any work, for a still of ``size`` (w, h) that extension
    ``fmt`` cannot hold: over :data:`MAX_ONE_PIECE` pixels where it is written in
    one piece (formats other than PNG and TIFF, or ``stream`` False: standard
    output), or a WebP over its side limit. The message names what can."""
    w, h = size
    what = "PNG and TIFF" if can_stream(".tif") else "PNG (TIFF with marblevideo[extras])"
    bands = f"{what} files are written in bands at any size"
    if fmt == ".webp" and max(w, h) > WEBP_MAX_SIDE:
        raise UsageError(f"{name}: {w}x{h} is over WebP's {WEBP_MAX_SIDE} pixels a side; {bands}")
    if (not stream or not can_stream(fmt)) and w * h > MAX_ONE_PIECE:
        kind = "to standard output" if not stream else f"as {fmt}"
        raise UsageError(
            f"{name}: {w}x{h} is over {MAX_ONE_PIECE} pixels, the most a still written "
            f"{kind} is rendered in one piece; {bands}"
        )


def band_rows(width: int, band_pixels: int = BAND_PIXELS) -> int:
    return max(1, band_pixels // max(1, width))


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


class PngStream:
    """Write an 8-bit RGB or RGBA PNG band by band (rows top to bottom), to the
    file at ``path`` or to a binary file object (left open by :meth:`close`)."""

    def __init__(
        self, path: str | os.PathLike | BinaryIO, width: int, height: int, channels: int, level=6
    ):
        if channels not in (3, 4):
            raise ValueError("channels must be 3 or 4")
        self._owned = not hasattr(path, "write")
        self.file = open(path, "wb") if self._owned else path  # noqa: SIM115  (see close())
        self.width, self.height, self.channels = width, height, channels
        self.rows = 0
        self._prev = np.zeros(width * channels, dtype=np.uint8)
        self._z = zlib.compressobj(level)
        color_type = 2 if channels == 3 else 6
        self.file.write(b"\x89PNG\r\n\x1a\n")
        header = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
        self.file.write(_chunk(b"IHDR", header))

    def write(self, band: np.ndarray) -> None:
        """Append rows: uint8 (n, width, channels)."""
        n = band.shape[0]
        flat = np.ascontiguousarray(band[..., : self.channels]).reshape(n, -1)
        up = np.empty((n, flat.shape[1] + 1), dtype=np.uint8)
        up[:, 0] = 2  # filter "Up": each byte minus the byte above (mod 256)
        up[0, 1:] = flat[0] - self._prev
        up[1:, 1:] = flat[1:] - flat[:-1]
        self._prev = flat[-1].copy()
        data = self._z.compress(up.tobytes())
        if data:
            self.file.write(_chunk(b"IDAT", data))
        self.rows += n

    def abort(self) -> None:
        """Close the file as it is, unfinished (the caller removes it)."""
        if self._owned:
            self.file.close()

    def close(self) -> None:
        """Finish the PNG; ValueError (the file closed) when rows are missing."""
        if self.file.closed or self._z is None:
            return
        try:
            if self.rows != self.height:
                raise ValueError(f"PNG got {self.rows} rows, expected {self.height}")
            self.file.write(_chunk(b"IDAT", self._z.flush()))
            self.file.write(_chunk(b"IEND", b""))
        finally:
            self._z = None
            if self._owned:
                self.file.close()


def png_bytes(pixels: np.ndarray, channels: int) -> bytes:
    """``pixels`` (uint8 (h, w, >= channels)) as a PNG of ``channels`` (3: RGB, 4:
    RGBA), by the writer of banded stills, one band: zlib alone, no OpenCV to
    import (faster than OpenCV's encoder, and smaller files, on marbled designs)."""
    out = io.BytesIO()
    png = PngStream(out, pixels.shape[1], pixels.shape[0], channels)
    png.write(pixels)
    png.close()
    return out.getvalue()


def _strips(band_iter: Iterator[np.ndarray], rows: int, channels: int) -> Iterator[bytes]:
    """Re-cut bands into deflated strips of ``rows`` rows (the last may be shorter):
    tifffile takes an iterator of strips as encoded bytes."""
    pending: np.ndarray | None = None
    for band in band_iter:
        band = band[..., :channels]
        pending = band if pending is None else np.concatenate([pending, band])
        n = len(pending) - len(pending) % rows
        for i in range(0, n, rows):
            yield zlib.compress(np.ascontiguousarray(pending[i : i + rows]).tobytes(), 6)
        pending = pending[n:]
    if pending is not None and len(pending):
        yield zlib.compress(np.ascontiguousarray(pending).tobytes(), 6)


def write_bands(
    path: str | os.PathLike,
    fmt: str,
    width: int,
    height: int,
    channels: int,
    band_iter: Iterator[np.ndarray],
) -> None:
    """Write the bands of ``band_iter`` (uint8 (n, width, >= channels), top to bottom)
    as one PNG (:class:`PngStream`) or TIFF (tifffile, deflate strips of 64 rows),
    holding one band at a time."""
    if fmt == ".png":
        png = PngStream(path, width, height, channels)
        try:
            for band in band_iter:
                png.write(band)
        except BaseException:  # an interrupt or a failure: not hidden by finishing
            png.abort()
            raise
        png.close()
        return
    import tifffile

    rows = 64
    tifffile.imwrite(
        path,
        data=_strips(band_iter, rows, channels),
        shape=(height, width, channels),
        dtype=np.uint8,
        photometric="rgb",
        extrasamples=("unassalpha",) if channels == 4 else None,
        rowsperstrip=rows,
        compression="zlib",
        bigtiff=height * width * channels > (1 << 32) - (1 << 26),
    )
