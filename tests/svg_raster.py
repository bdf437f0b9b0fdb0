"""SVG rasterized by an independent renderer (cairosvg), and compared with rasters."""

from __future__ import annotations

import numpy as np
import pytest
from tolerances import SVG_LEVELS

cairosvg = pytest.importorskip("cairosvg", reason="cairosvg (test extra) rasterizes the SVG")


def rasterize(svg: str, size: tuple[int, int]) -> np.ndarray:
    import cv2

    png = cairosvg.svg2png(bytestring=svg.encode(), output_width=size[0], output_height=size[1])
    bgra = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
    return cv2.cvtColor(bgra, cv2.COLOR_BGRA2RGBA)


def agreement(a: np.ndarray, b: np.ndarray, tol: int = SVG_LEVELS) -> float:
    """Fraction of pixels whose RGB differ by at most ``tol`` (edge pixels are
    antialiased differently: cairo by area, the kernel by its subsample pattern)."""
    d = np.abs(a[..., :3].astype(int) - b[..., :3].astype(int)).max(axis=-1)
    return float((d <= tol).mean())
