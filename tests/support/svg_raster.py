"""SVG rasterized by an independent renderer (cairosvg), and compared with rasters."""

from __future__ import annotations

import numpy as np
import pytest
from tolerances import SVG_LEVELS

cairosvg = pytest.importorskip("cairosvg", reason="cairosvg (test extra) rasterizes the SVG")


def rasterize(svg: str, size: tuple[int, int], supersample: int = 1) -> np.ndarray:
    """RGBA pixels of ``svg`` at ``size``; with ``supersample`` k, rasterized k
    times finer and averaged over each k x k block (each pixel by area)."""
    import cv2

    w, h = size[0] * supersample, size[1] * supersample
    png = cairosvg.svg2png(bytestring=svg.encode(), output_width=w, output_height=h)
    bgra = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
    rgba = cv2.cvtColor(bgra, cv2.COLOR_BGRA2RGBA)
    if supersample > 1:
        rgba = cv2.resize(rgba, size, interpolation=cv2.INTER_AREA)
    return rgba


def path_points(svg: str, index: int = 0) -> np.ndarray:
    """The vertices (n, 2) of the ``index``-th <path> of ``svg`` (absolute M and L,
    relative l, z), parsed by the SVG number grammar independently."""
    import re

    path = svg.split("<path")[index + 1]
    start = path.index('d="') + 3
    d = path[start : path.index('"', start)]
    assert d[0] == "M" and d.endswith("z")
    number = r"-?(?:\d+\.?\d*|\.\d+)"
    points, here = [], np.zeros(2)
    for command, args in re.findall(r"([MLlz])([^MLlz]*)", d):
        values = np.array([float(v) for v in re.findall(number, args)]).reshape(-1, 2)
        for v in values:
            here = here + v if command == "l" else v
            points.append(here)
    return np.array(points)


def agreement(a: np.ndarray, b: np.ndarray, tol: int = SVG_LEVELS) -> float:
    """Fraction of pixels whose RGB differ by at most ``tol`` (edge pixels are
    antialiased differently: cairo by area, the kernel by its subsample pattern)."""
    d = np.abs(a[..., :3].astype(int) - b[..., :3].astype(int)).max(axis=-1)
    return float((d <= tol).mean())
