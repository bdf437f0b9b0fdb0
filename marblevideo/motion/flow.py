"""One frame's motion: the luma, its reduction, DIS optical flow against the previous
frame, the frame's dominant motion taken out, and the moving regions it leaves.

Conventions: a frame's pixel (i, j) covers [i, i+1] x [j, j+1] of *frame
coordinates* (its centre at (i + 0.5, j + 0.5)), as the contract's geometry says.
The analysis runs on the luma reduced by an integer factor ``k``
(:func:`reduction`: the longer side about :data:`REDUCED_SIDE` points, 1280x720 ->
320x180) with area averaging, so reduced point (u, v) covers frame pixels
[k u, k u + k) x [k v, k v + k) and its centre is at (k (u + 0.5), k (v + 0.5)).

The flow is OpenCV's DIS (``DISOPTICAL_FLOW_PRESET_ULTRAFAST``, with its finest scale
brought down from 2 to 1 and its patches from 8 points every 4 to 4 points every 2,
so that a disc of 40 frame pixels in a 640x360 frame still spans many patches and is
followed at 600 px/s), computed *backwards*, from the current frame to the previous
one, so that it is defined where things are now: a moving region lies where the object is in the
current frame, not where it was. Each computation is seeded with the previous one
(a motion under way is followed from frame to frame). DIS gives the same flow
whatever OpenCV's thread count (its work is split by rows, each computed alike), so
the analysis is deterministic bit for bit without setting it.
The dominant motion (a pan, a shaken camera) is the per-axis median of the flow
(:func:`dominant`), subtracted; what remains, at least ``threshold`` canvas units
per second, is moving.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

#: The analysed luma's longer side, about (the reduction factor is an integer).
REDUCED_SIDE = 320
#: The shortest side analysed (DIS needs 12 points at least): a frame whose shorter
#: side is below it shows no motion.
MIN_SIDE = 16
#: Reduced points along each edge left out of the moving mask: content entering or
#: leaving a shaken or panned frame has no match there.
MARGIN = 2
#: The smallest moving region kept, in reduced points (smaller ones are specks).
MIN_POINTS = 6
#: Whether each flow starts from the last one.
SEED = True
#: Reduced points per frame apart from the dominant motion from which a point's
#: flow is carried to where it goes, to seed the next frame's.
CARRY = 0.5
#: A region's own extent: its points at least this share of its 90th-percentile speed.
CORE = 0.5
_OPEN = np.ones((3, 3), np.uint8)


def luma(frame: np.ndarray) -> np.ndarray:
    """The 8-bit luma of an HxWx3 RGB, HxWx4 RGBA or HxW luma uint8 frame: OpenCV's
    fixed-point BT.601 weights (0.299 R + 0.587 G + 0.114 B, rounded), alpha
    ignored; a luma frame is returned as it is. The one definition every caller
    uses, so that a file and a live session see the same luma: feed it the same
    kind of frame everywhere (an I420 frame's Y plane is not the luma of its RGB
    conversion: its range and matrix differ)."""
    if frame.ndim == 2:
        return np.ascontiguousarray(frame, dtype=np.uint8)
    if frame.ndim != 3 or frame.shape[2] not in (3, 4):
        raise ValueError(f"expected an HxW, HxWx3 or HxWx4 frame, got shape {frame.shape}")
    code = cv2.COLOR_RGB2GRAY if frame.shape[2] == 3 else cv2.COLOR_RGBA2GRAY
    return cv2.cvtColor(np.ascontiguousarray(frame, dtype=np.uint8), code)


def reduction(width: int, height: int) -> int:
    """The integer factor the luma of a ``width`` x ``height`` frame is reduced by:
    its longer side to about :data:`REDUCED_SIDE`, its shorter side kept at least
    :data:`MIN_SIDE` where it can be."""
    k = max(1, round(max(width, height) / REDUCED_SIDE))
    return max(1, min(k, min(width, height) // MIN_SIDE))


def reduce(gray: np.ndarray, k: int) -> np.ndarray:
    """``gray`` averaged over k x k blocks (the last partial row and column dropped)."""
    h, w = gray.shape
    if k == 1:
        return gray
    return cv2.resize(
        gray[: h - h % k, : w - w % k], (w // k, h // k), interpolation=cv2.INTER_AREA
    )


@dataclass(frozen=True)
class Region:
    """A moving region of one frame: ``center`` in frame coordinates, ``area`` in
    frame pixels, ``speed`` the 90th percentile of its points' remaining motion in
    canvas units per second."""

    center: tuple[float, float]
    area: float
    speed: float


class Flow:
    """The DIS flow between consecutive reduced lumas, each seeded with the last."""

    def __init__(self) -> None:
        self.dis = cv2.DISOpticalFlow_create(cv2.DISOPTICAL_FLOW_PRESET_ULTRAFAST)
        self.dis.setFinestScale(1)
        self.dis.setPatchSize(4)
        self.dis.setPatchStride(2)
        self.dis.setUseSpatialPropagation(True)
        self.previous: np.ndarray | None = None
        self.flow: np.ndarray | None = None
        #: the dominant motion of the last flow returned (reduced points per frame)
        self.shift = (0.0, 0.0)

    def reset(self) -> None:
        self.previous, self.flow = None, None

    def step(self, small: np.ndarray) -> np.ndarray | None:
        """The motion (dx, dy) per reduced point, from the previous luma to ``small``,
        at the points of ``small`` (HxWx2 float32), or None for the first frame (and
        for a luma smaller than :data:`MIN_SIDE`)."""
        previous, self.previous = self.previous, small
        if min(small.shape) < MIN_SIDE:
            self.previous = None  # too small to analyse
        if previous is None or previous.shape != small.shape or self.previous is None:
            self.flow = None
            return None
        # DIS starts from the flow it is given when it has the images' size
        seed = None if self.flow is None or not SEED else self.flow.copy()
        flow = self.dis.calc(small, previous, seed)
        mx, my = dominant(flow)
        self.flow, self.shift = carried(flow, (mx, my)), (-mx, -my)
        return -flow


def dominant(flow: np.ndarray) -> tuple[float, float]:
    """The frame's dominant motion: the per-axis median of the flow at every other
    point of every other row (a pan or a shake moves them all)."""
    sample = flow[::2, ::2].reshape(-1, 2)
    return float(np.median(sample[:, 0])), float(np.median(sample[:, 1]))


def carried(flow: np.ndarray, shift: tuple[float, float]) -> np.ndarray:
    """The seed of the next frame's (backward) flow: each point that moves apart
    from the dominant motion carried on by one more frame of its own motion (where
    a fast object will be, its flow already), the fastest winning where several
    land on one point; the other points keep their flow. ``shift``: its
    :func:`dominant` motion."""
    h, w = flow.shape[:2]
    mx, my = shift
    dx, dy = flow[..., 0] - np.float32(mx), flow[..., 1] - np.float32(my)
    apart = dx * dx + dy * dy  # squared
    vs, us = np.nonzero(apart > CARRY * CARRY)
    if len(us) == 0:
        return flow
    b = flow[vs, us]
    x = np.rint(us - b[:, 0]).astype(np.int64)
    y = np.rint(vs - b[:, 1]).astype(np.int64)
    inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
    order = np.argsort(-apart[vs, us][inside], kind="stable")
    where = (y[inside] * w + x[inside])[order]
    where, first = np.unique(where, return_index=True)  # the fastest at each point
    seed = flow.copy()
    seed.reshape(-1, 2)[where] = b[inside][order][first]
    return seed


def moving(
    flow: np.ndarray,
    scale: tuple[float, float],
    threshold: float,
    shift: tuple[float, float] | None = None,
) -> np.ndarray:
    """The remaining speed per point (``scale``: reduced points per frame -> canvas
    units per second, per axis), the dominant motion (``shift``, else
    :func:`dominant`'s) taken out, and zero where it is under ``threshold`` or in the margin."""
    mx, my = dominant(flow) if shift is None else shift
    dx = (flow[..., 0] - mx) * scale[0]
    dy = (flow[..., 1] - my) * scale[1]
    speed = np.sqrt(dx * dx + dy * dy)
    speed[speed < threshold] = 0.0
    m = MARGIN
    speed[:m], speed[-m:], speed[:, :m], speed[:, -m:] = 0.0, 0.0, 0.0, 0.0
    return speed


def regions(speed: np.ndarray, k: int) -> list[Region]:
    """The moving regions of ``speed`` (> 0 where moving): connected components of
    the mask after a 3x3 opening, those of at least :data:`MIN_POINTS` points.
    Each region's speed is its points' 90th-percentile speed, its own extent its
    points at least half that
    (the flow's smear past an object's edge, slower, is left out); its centre is
    their centroid in frame coordinates, its area their frame pixels."""
    mask = cv2.morphologyEx((speed > 0).astype(np.uint8), cv2.MORPH_OPEN, _OPEN)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    found = []
    for label in range(1, count):
        if stats[label, cv2.CC_STAT_AREA] < MIN_POINTS:
            continue
        x, y, w, h = (int(stats[label, c]) for c in range(4))
        box = labels[y : y + h, x : x + w] == label
        values = speed[y : y + h, x : x + w]
        top = float(np.percentile(values[box], 90))
        vs, us = np.nonzero(box & (values >= CORE * top))
        center = (k * (x + float(us.mean()) + 0.5), k * (y + float(vs.mean()) + 0.5))
        found.append(Region(center, float(len(us) * k * k), top))
    return found
