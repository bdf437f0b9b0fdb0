"""Antialiasing subsample patterns of the recipe format.

Each pattern is a list of (dx, dy, weight): offsets from the pixel centre in
output pixels, weights summing to 1. The pixel is the weighted mean of its
subsamples. One table serves the reference and the kernel (which receives it
in a small buffer), so the two cannot disagree.
"""

from __future__ import annotations

import numpy as np


def _cells(n: int, cells: list[tuple[int, int]]) -> list[tuple[float, float, float]]:
    return [((c + 0.5) / n - 0.5, (r + 0.5) / n - 0.5, 1.0 / len(cells)) for c, r in cells]


PATTERNS: dict[str, list[tuple[float, float, float]]] = {
    "none": [(0.0, 0.0, 1.0)],
    "rgss": [
        (-1 / 8, -3 / 8, 0.25),
        (3 / 8, -1 / 8, 0.25),
        (1 / 8, 3 / 8, 0.25),
        (-3 / 8, 1 / 8, 0.25),
    ],
    "quincunx": [(0.0, 0.0, 0.5)]
    + [(sx * 0.5, sy * 0.5, 0.125) for sy in (-1, 1) for sx in (-1, 1)],
    "checker4": _cells(4, [(c, r) for r in range(4) for c in range(4) if (c + r) % 2 == 0]),
    "grid4": _cells(4, [(c, r) for r in range(4) for c in range(4)]),
    "rooks8": _cells(8, list(enumerate((3, 7, 1, 5, 0, 4, 2, 6)))),
}


def pattern(name: str) -> np.ndarray:
    """The pattern ``name`` as a float64 array of shape (n, 3): dx, dy, weight."""
    return np.array(PATTERNS[name], dtype=np.float64)
