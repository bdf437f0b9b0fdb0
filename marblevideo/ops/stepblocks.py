"""The kernel's culling data of a stroke's steps: consecutive steps in blocks of
BLOCK_STEPS, each with a circle that holds every point any of its steps can move.

A block's circle has its centre at the middle of the box of its steps' ends
A, B and its radius the ends' farthest distance from there plus w: nothing
farther from every A and B than w moves, so nothing outside the circle moves
while the block is walked (a point a step keeps, the next step sees unmoved).
The kernel skips a block where no lane is inside its circle, which is exact:
the radius is grown by RADIUS_MARGIN of itself and of the coordinates' size,
far more than float32 rounding of the circle, the centres and the distances.
Blocks are laid from the first step on, so a prefix of a stroke's steps has the
whole blocks of the longer stroke's prefix (:func:`prefix_blocks`).
"""

from __future__ import annotations

import numpy as np

#: Steps per block (the last block of a stroke may hold fewer).
BLOCK_STEPS = 8
#: Floats per block in the kernel's data: the circle's cx, cy and radius squared.
BLOCK_FLOATS = 3
#: The circle's radius grown by this share of itself and of its centre's size.
RADIUS_MARGIN = 1e-4


def block_rows(centres: np.ndarray, halves: np.ndarray, width: float) -> np.ndarray:
    """(ceil(n / BLOCK_STEPS), BLOCK_FLOATS) circles of the steps' ``centres`` and
    ``halves`` ((n, 2) each, forward order; A = centre + half, B = centre - half)."""
    n = len(centres)
    if n == 0:
        return np.zeros((0, BLOCK_FLOATS))
    pad = -n % BLOCK_STEPS  # the last step repeated: the same ends, the same circle
    ends = np.concatenate([centres + halves, centres - halves], axis=1)
    ends = np.concatenate([ends, np.repeat(ends[-1:], pad, axis=0)])
    ends = ends.reshape(-1, 2 * BLOCK_STEPS, 2)
    mid = (ends.min(axis=1) + ends.max(axis=1)) / 2
    far = np.sqrt(((ends - mid[:, None, :]) ** 2).sum(axis=2)).max(axis=1)
    radius = far + width
    radius += RADIUS_MARGIN * (radius + np.abs(mid).max(axis=1))
    return np.column_stack([mid, radius * radius])


def prefix_blocks(
    longer: tuple[float, ...], at: int, centres: np.ndarray, halves: np.ndarray, width: float
) -> tuple[float, ...]:
    """The circles of a stroke's acting steps whose first ``at`` (a multiple of
    BLOCK_STEPS) are a longer stroke's, whose circles are ``longer`` (its
    block_rows, flattened): those blocks taken from it, then the blocks of the
    steps from ``at`` on, ``centres`` and ``halves``, laid afresh."""
    return longer[: at // BLOCK_STEPS * BLOCK_FLOATS] + tuple(
        block_rows(centres, halves, width).ravel().tolist()
    )
