"""One frame's motion: the luma, its reduction, DIS optical flow against the previous
frame, the frame's dominant motion taken out, and the moving regions it leaves.

Conventions: a frame's pixel (i, j) covers [i, i+1] x [j, j+1] of *frame
coordinates* (its centre at (i + 0.5, j + 0.5)), as the contract's geometry says.
The analysis runs on the luma reduced by an integer factor ``k``
(:func:`reduction`: the longer side about :data:`REDUCED_SIDE` points, 1280x720 ->
320x180) with area averaging (:func:`reduce`), so reduced point (u, v) covers
frame pixels [k u, k u + k) x [k v, k v + k) and its centre is at
(k (u + 0.5), k (v + 0.5)).

The flow is OpenCV's DIS (``DISOPTICAL_FLOW_PRESET_ULTRAFAST``, with its finest scale
brought down from 2 to 1 and its patches from 8 points every 4 to 4 points every 2,
so that a disc of 40 frame pixels in a 640x360 frame still spans many patches and is
followed at 600 px/s), computed *backwards*, from the current frame to the previous
one, so that it is defined where things are now: a moving region lies where the object is in the
current frame, not where it was. Each computation is seeded with the previous one
(a motion under way is followed from frame to frame). DIS gives the same flow
whatever OpenCV's thread count (its work is split by rows, each computed alike), so
the analysis is deterministic bit for bit without setting it. DIS is most of
the analysis' cost (about 4 ms of CPU a frame at 1280x720 here, BENCHMARKS.md):
OpenCV computes 4-point patches without SIMD, but 8-point ones, spatial
propagation off, fewer descent iterations or no patch mean normalization each
lose a contract case (tests/test_motion.py).
The dominant motion (a pan, a shaken camera) is the per-axis median of the flow
(:func:`dominant`), subtracted; what remains, at least ``threshold`` canvas units
per second, is moving. What follows DIS is computed only at the points that may
move apart from the dominant motion (outside a square around it, found by one
``cv2.inRange``; :class:`Motion`), with the same float32 operations as over the
whole grid, so it gives the whole grid's results bit for bit at a fraction of
its cost.
"""

from __future__ import annotations

import math
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
    ignored; a luma frame is returned as it is (a view, not copied, where its
    rows are contiguous). The one definition every caller
    uses, so that a file and a live session see the same luma: feed it the same
    kind of frame everywhere (an I420 frame's Y plane is not the luma of its RGB
    conversion: its range and matrix differ)."""
    if frame.ndim == 2:  # a decoder's Y plane is read where it lies (rows padded)
        if frame.dtype == np.uint8 and frame.strides[1] == 1 and frame.strides[0] > 0:
            return frame
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
    """``gray`` averaged over k x k blocks (the last partial row and column
    dropped), each average rounded; an even k by halving in 2 x 2 blocks first
    (rounded at each halving: OpenCV's fast path, a third of the time of one
    4 x 4 average)."""
    h, w = gray.shape
    if k == 1:  # DIS takes contiguous rows only (a decoder's plane has padded ones)
        return np.ascontiguousarray(gray)
    gray = gray[: h - h % k, : w - w % k]
    while k % 2 == 0 and k > 2:
        h, w = gray.shape
        gray = cv2.resize(gray, (w // 2, h // 2), interpolation=cv2.INTER_AREA)
        k //= 2
    h, w = gray.shape
    return cv2.resize(gray, (w // k, h // k), interpolation=cv2.INTER_AREA)


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

    def step(self, small: np.ndarray, low: float = 0.0) -> Motion | None:
        """The remaining motion from the previous luma to ``small`` (reduced points
        per frame), the dominant motion (:attr:`shift`) taken out, at the points of
        ``small`` where it may be at least ``low`` long, squared (:func:`reach`), or
        :data:`CARRY`; None for the first frame (and for a luma smaller than
        :data:`MIN_SIDE`)."""
        previous, self.previous = self.previous, small
        if min(small.shape) < MIN_SIDE:
            self.previous = None  # too small to analyse
        if previous is None or previous.shape != small.shape or self.previous is None:
            self.flow = None
            return None
        # DIS starts from the flow it is given when it has the images' size (and
        # writes its result over it: the seed is the flow's own, made for this call)
        seed = self.flow if SEED else None
        flow = self.dis.calc(small, previous, seed)
        mx, my = dominant(flow)
        low = min(low, CARRY * CARRY)
        at = _apart(flow, mx, my, low)
        pairs = flow.reshape(-1).view(np.int64)[at]  # each point's (x, y) as one item
        # the backward flow's remaining motion, turned forward
        dx = np.float32(mx) - pairs.view(np.float32)[0::2]
        dy = np.float32(my) - pairs.view(np.float32)[1::2]
        apart = dx * dx  # squared
        apart += dy * dy
        self.flow, self.shift = carried(flow, at, pairs, apart), (-mx, -my)
        return Motion(small.shape, at, dx, dy, apart, low)


@dataclass(frozen=True)
class Motion:
    """One frame's remaining motion (reduced points per frame) on a ``shape``
    (H, W) grid, at the points ``at`` (flat indices, increasing): ``dx``, ``dy``
    and ``apart``, dx * dx + dy * dy (float32, each operation rounded, as over the
    whole grid). The points left out are those where ``apart`` is surely under
    ``low``."""

    shape: tuple[int, int]
    at: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    apart: np.ndarray
    low: float


def _apart(flow: np.ndarray, mx: float, my: float, low: float) -> np.ndarray:
    """The flat indices of the points of ``flow`` outside a square around (mx, my)
    (increasing): all of those where the squared distance may be ``low`` or more
    (the square's half side is 0.9 sqrt(low / 2), far from float32's rounding)."""
    h, w = flow.shape[:2]
    r = 0.9 * math.sqrt(max(low, 0.0) / 2)
    if not r > 1e-4 * (1 + abs(mx) + abs(my)):
        return np.arange(h * w)
    near = cv2.inRange(flow, (mx - r, my - r), (mx + r, my + r))
    return np.flatnonzero(near.ravel() == 0)


def reach(scale: tuple[float, float], threshold: float) -> float:
    """The squared remaining motion (reduced points per frame) under which a
    point's speed, at ``scale`` (:func:`moving`), is surely under ``threshold``:
    what :meth:`Flow.step` needs for :func:`moving` (0 where any may reach it)."""
    top = max(abs(float(np.float32(scale[0]))), abs(float(np.float32(scale[1]))))
    low = (float(np.float32(threshold)) / top) ** 2 * 0.999 if top > 0 else 0.0
    return low if math.isfinite(low) else 0.0


def dominant(flow: np.ndarray) -> tuple[float, float]:
    """The frame's dominant motion: the per-axis median of the flow at every other
    point of every other row (a pan or a shake moves them all), as ``np.median``
    (the mean of the middle two of an even count, a float32 sum halved)."""
    a = flow[::2, ::2].transpose(2, 0, 1).reshape(2, -1)  # a copy: not contiguous
    if np.may_share_memory(a, flow):
        a = a.copy()
    a.sort(axis=1)  # NumPy's SIMD sort: faster here than a partition
    half = a.shape[1] // 2
    if a.shape[1] % 2:
        return float(a[0, half]), float(a[1, half])
    mid = (a[:, half - 1] + a[:, half]) / np.float32(2)  # np.mean's float32 sum, halved
    return float(mid[0]), float(mid[1])


def carried(flow: np.ndarray, at: np.ndarray, pairs: np.ndarray, apart: np.ndarray) -> np.ndarray:
    """The seed of the next frame's (backward) flow: each point that moves apart
    from the dominant motion carried on by one more frame of its own motion (where
    a fast object will be, its flow already), the fastest winning where several
    land on one point (of equal speeds, the first in row-major order); the other
    points keep their flow. ``at``, ``apart``: :class:`Motion`'s (every point whose
    ``apart`` may pass :data:`CARRY` squared), ``pairs``: the flow there, (x, y)
    as one int64 item. Written over ``flow``, returned."""
    h, w = flow.shape[:2]
    go = np.flatnonzero(apart > CARRY * CARRY)
    if len(go) == 0:
        return flow
    at, b, apart = at[go], pairs[go], apart[go]
    vs, us = np.divmod(at, w)
    x = np.rint(us - b.view(np.float32)[0::2]).astype(np.int64)
    y = np.rint(vs - b.view(np.float32)[1::2]).astype(np.int64)
    # inside: 0 <= x < w and 0 <= y < h (a negative one, unsigned, is huge)
    inside = np.flatnonzero((x.view(np.uint64) < w) & (y.view(np.uint64) < h))
    # one stable sort by (target point, speed down): a speed's float32 bits, as
    # an integer, order as it does (it is >= 0)
    bits = apart[inside].view(np.int32).astype(np.int64)
    key = (y[inside] * w + x[inside]) << 31 | (np.int64(0x7FFFFFFF) - bits)
    order = np.argsort(key, kind="stable")
    where = key[order] >> 31
    first = np.ones(len(where), bool)
    first[1:] = where[1:] != where[:-1]
    flow.reshape(-1).view(np.int64)[where[first]] = b[inside[order[first]]]
    return flow


@dataclass(frozen=True)
class Speed:
    """The remaining speed of one frame's moving points on a ``shape`` (H, W) grid:
    ``points``, their flat indices (increasing), and ``speed`` there (float32,
    canvas units per second); every other point is under the threshold, in the
    margin or still."""

    shape: tuple[int, int]
    points: np.ndarray
    speed: np.ndarray


def moving(motion: Motion, scale: tuple[float, float], threshold: float) -> Speed:
    """The remaining speed of ``motion`` (:meth:`Flow.step`'s, for at least this
    :func:`reach`; ``scale``: reduced points per frame -> canvas units per second,
    per axis): sqrt((dx sx)^2 + (dy sy)^2) in float32, each operation rounded,
    where it is at least ``threshold`` and not zero, outside the margin."""
    low = reach(scale, threshold)
    if low < motion.low:
        raise ValueError(f"the motion leaves out points under {motion.low}, not {low}")
    h, w = motion.shape
    sx, sy = np.float32(scale[0]), np.float32(scale[1])
    pick = np.flatnonzero(motion.apart >= np.float32(low)) if low > 0 else slice(None)
    at = motion.at[pick]
    vs, us = np.divmod(at, w)
    m = MARGIN
    keep = (vs >= m) & (vs < h - m) & (us >= m) & (us < w - m)
    at = at[keep]
    dx = motion.dx[pick][keep] * sx
    dy = motion.dy[pick][keep] * sy
    np.multiply(dx, dx, out=dx)
    np.multiply(dy, dy, out=dy)
    np.add(dx, dy, out=dx)
    fast = np.sqrt(dx, out=dx)
    keep = np.flatnonzero((fast >= threshold) & (fast > 0))
    return Speed(motion.shape, at[keep], fast[keep])


def regions(found: Speed, k: int) -> list[Region]:
    """The moving regions of ``found``: connected components of its points after
    a 3x3 opening, those of at least :data:`MIN_POINTS` points.
    Each region's speed is its points' 90th-percentile speed, its own extent its
    points at least half that
    (the flow's smear past an object's edge, slower, is left out); its centre is
    their centroid in frame coordinates, its area their frame pixels. The
    components are labelled in the box around the points (its corner at even
    rows and columns, so labelled in the same order as over the whole frame)."""
    if len(found.points) == 0:
        return []
    h, w = found.shape
    rows, cols = np.divmod(found.points, w)  # rows in increasing order
    y0, y1 = max(0, (int(rows[0]) - 2) // 2 * 2), min(h, int(rows[-1]) + 3)
    x0, x1 = max(0, (int(cols.min()) - 2) // 2 * 2), min(w, int(cols.max()) + 3)
    inside = (rows - y0) * (x1 - x0) + (cols - x0)
    speed = np.zeros((y1 - y0, x1 - x0), np.float32)
    speed.ravel()[inside] = found.speed
    mask = np.zeros(speed.shape, np.uint8)
    mask.ravel()[inside] = 1
    mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, _OPEN)
    # 16-bit labels where they suffice (after the opening each region holds a 3x3
    # block: at most a ninth of the points are regions): twice as fast
    ltype = cv2.CV_16U if mask.size // 9 < 65535 else cv2.CV_32S
    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8, ltype=ltype)
    result = []
    for label in range(1, count):
        if stats[label, cv2.CC_STAT_AREA] < MIN_POINTS:
            continue
        x, y, bw, bh = (int(stats[label, c]) for c in range(4))
        box = labels[y : y + bh, x : x + bw] == label
        values = speed[y : y + bh, x : x + bw]
        top = _top(values[box])
        ys, xs = np.nonzero(box & (values >= CORE * top))
        n = len(xs)
        cx, cy = x0 + x + float(xs.sum()) / n + 0.5, y0 + y + float(ys.sum()) / n + 0.5
        result.append(Region((k * cx, k * cy), float(n * k * k), top))
    return result


def _top(values: np.ndarray) -> float:
    """The 90th percentile of ``values`` (linear between the closest ranks, as
    ``np.percentile``'s default), by one partition."""
    at = 0.9 * (values.size - 1)
    low = int(at)
    high = min(low + 1, values.size - 1)
    part = np.partition(values, (low, high))
    a, b = float(part[low]), float(part[high])
    return a + (b - a) * (at - low)
