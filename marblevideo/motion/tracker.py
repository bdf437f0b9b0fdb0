"""Frames in, motion strokes out: the contract's ``motion`` rules (docs/recipe-format.md).

:class:`MotionTracker` sees the input's frames in order and follows the moving
regions that :mod:`marblevideo.motion.flow` finds in each (those narrower than
the smallest ``width`` are specks, left out): a region is matched to the followed
one nearest to its predicted centre (moving on as between its last two frames;
within a gate of the region's radius plus the distance it moved last, at least 2
reduced points), the regions with the largest area x speed first, at most
``max_strokes`` followed at once. A region followed for 3 consecutive frames
(whose centre moved as its flow says, see :meth:`MotionTracker._extend`) becomes a
stroke (its width the median diameter of those 3 frames, clamped to ``width``);
the stroke grows by one point a frame while its
region is seen and ends once it has been lost for more than :data:`LOST` seconds.
A stroke that would pass :data:`~marblevideo.ops.stroke.MAX_POINTS` points or
:data:`~marblevideo.ops.stroke.MAX_STEPS` steps ends there, and its region goes on
as a new stroke from its last point. Points are rounded to :data:`DECIMALS`
decimals of a canvas unit; times are the frames' own (not rounded). A stroke
begins at the second of the 3 frames that made it (its stylus is at its first point
then, so it is still the identity there) and reaches the third's centre at the
third: it is never drawn before it is seen, so a take (these strokes as ordinary
ops) replays the frames exactly.

Everything is causal and deterministic: the strokes after a frame depend only on
the frames seen so far, through float64 NumPy and OpenCV's DIS, whose flow does not
depend on its thread count (see :mod:`marblevideo.motion.flow`).
"""

from __future__ import annotations

import math
import statistics

import numpy as np

from marblevideo.motion.flow import (
    Flow,
    Region,
    luma,
    moving,
    reach,
    reduce,
    reduction,
    regions,
)
from marblevideo.motion.spec import MotionSpec
from marblevideo.ops.stroke import MAX_POINTS, MAX_STEPS
from marblevideo.ops.stylus import step_total

#: Seconds a followed region may be lost before its stroke ends.
LOST = 0.25
#: Consecutive frames that make a followed region a stroke.
FRAMES = 3
#: How far (a factor) a new region's centre speed may be from its flow speed.
AGREE = 1.5
DECIMALS = 2
#: Share of the analysed points moving at which :meth:`MotionTracker.level` is 1.
FULL_LEVEL = 0.1


class _Stroke:
    """One motion stroke as it grows: canvas points, times, a fixed width; its op
    dict made once per change (what strokes() and take() hand out)."""

    def __init__(self, points: list, times: list, width: float, spec: MotionSpec) -> None:
        self.points, self.times, self.width, self.spec = points, times, width, spec
        self.length = sum(math.dist(a, b) for a, b in zip(points, points[1:], strict=False))
        self._op: dict | None = None

    def room(self, point: tuple[float, float]) -> bool:
        """Whether one more point keeps it within the stroke op's limits."""
        length = self.length + math.dist(self.points[-1], point)
        return len(self.points) < MAX_POINTS and step_total(length, self.width) <= MAX_STEPS

    def add(self, point: tuple[float, float], t: float) -> None:
        self.length += math.dist(self.points[-1], point)
        self.points.append(point)
        self.times.append(t)
        self._op = None

    def heal(self) -> tuple[float, float]:
        """Its ``heal`` [last + memory, last + memory + heal]."""
        t0 = self.times[-1] + self.spec.memory
        return t0, t0 + self.spec.heal

    def op(self) -> dict:
        if self._op is None:
            self._op = {
                "type": "stroke",
                "points": [list(p) for p in self.points],
                "times": list(self.times),
                "width": self.width,
                "drag": self.spec.gain,
                "heal": list(self.heal()),
            }
        return self._op


class _Follow:
    """A followed region: its recent frames and, once it is one, its stroke."""

    def __init__(self, point: tuple[float, float], t: float, diameter: float) -> None:
        self.seen = [(point, t, diameter)]
        self.stroke: int | None = None
        self.step = 0.0  # how far it moved between its last two frames (canvas units)

    @property
    def point(self) -> tuple[float, float]:
        return self.seen[-1][0]

    @property
    def predicted(self) -> tuple[float, float]:
        """Where it would be in the next frame, moving on as between its last two."""
        if len(self.seen) < 2:
            return self.point
        (x0, y0), (x1, y1) = self.seen[-2][0], self.seen[-1][0]
        return (2 * x1 - x0, 2 * y1 - y0)

    @property
    def last(self) -> float:
        return self.seen[-1][1]


class MotionTracker:
    """The motion strokes of a stream of frames (see the module's doc).

    ``to_canvas`` = (a, b, c, d) maps a point (px, py) of frame coordinates (pixel
    centres at +0.5) to canvas units: (px a + c, py b + d)."""

    def __init__(self, spec: MotionSpec, to_canvas: tuple[float, float, float, float]) -> None:
        self.spec = spec
        self.to_canvas = tuple(float(v) for v in to_canvas)
        self.flow = Flow()
        self._strokes: list[_Stroke] = []
        self._live: list[int] = []  # indices of the strokes not yet healed
        self._follows: list[_Follow] = []
        self._regions: list[dict] = []
        self._level = 0.0
        self._t: float | None = None
        self._size: tuple[int, int] | None = None

    # ----------------------------------------------------------------- results

    def strokes(self) -> list[dict]:
        """The stroke ops not completely healed at the last frame's time, in the order
        they began (what is rendered then, after the recipe's ops). The dicts are the
        tracker's own, the same objects until their stroke grows (so comparing them
        is cheap): copy one before changing it."""
        return [self._strokes[n].op() for n in self._live]

    def take(self) -> list[dict]:
        """Every stroke op made so far, healed ones too, in the order they began
        (the tracker's own dicts, as :meth:`strokes`)."""
        return [s.op() for s in self._strokes]

    def regions(self) -> list[dict]:
        """The regions followed in the last frame: ``center`` [x, y] and ``radius``
        in canvas units, ``speed`` in canvas units per second, ``stroke`` their
        stroke's index in :meth:`take` (None while not yet a stroke)."""
        return [dict(r) for r in self._regions]

    def level(self) -> float:
        """0..1: the share of the last frame's analysed points whose remaining motion
        is at least ``threshold``, over :data:`FULL_LEVEL` (1 from a tenth on)."""
        return self._level

    def _heal_live(self, t: float) -> None:
        """Forget the strokes completely healed at ``t`` (their heal's end, or its
        start when it takes no time, reached). A growing stroke is never healed:
        its last point is at most LOST old and ``memory`` is longer."""
        self._live = [n for n in self._live if t < self._strokes[n].heal()[1]]

    # ----------------------------------------------------------------- frames

    def see(self, frame: np.ndarray, t: float) -> None:
        """Take the frame shown at ``t`` seconds (times increasing)."""
        gray = luma(frame)
        h, w = gray.shape
        k = reduction(w, h)
        if self._size != (w, h):
            self._size = (w, h)
            self.flow.reset()
        previous, self._t = self._t, float(t)
        self._heal_live(float(t))
        a, b = abs(self.to_canvas[0]), abs(self.to_canvas[1])
        dt = t - previous if previous is not None else 0.0
        scale = (k * a / dt, k * b / dt) if dt > 0 else (0.0, 0.0)
        threshold = self.spec.threshold
        motion = self.flow.step(reduce(gray, k), reach(scale, threshold) if dt > 0 else 1.0)
        if motion is None or previous is None or not t > previous:
            self._regions, self._level = [], 0.0
            return
        speed = moving(motion, scale, threshold)
        self._level = min(1.0, len(speed.points) / math.prod(speed.shape) / FULL_LEVEL)
        speck = self.spec.width[0] ** 2 * math.pi / 4 / (a * b)  # frame pixels
        found = [r for r in regions(speed, k) if r.area >= speck]
        found.sort(key=lambda r: -r.area * r.speed)
        self._follow(found[: self.spec.max_strokes], float(t), k * max(a, b))

    def _canvas(self, region: Region) -> tuple[tuple[float, float], float]:
        a, b, c, d = self.to_canvas
        x, y = region.center
        point = (round(x * a + c, DECIMALS), round(y * b + d, DECIMALS))
        return point, 2.0 * math.sqrt(region.area * abs(a * b) / math.pi)

    def _follow(self, found: list[Region], t: float, unit: float) -> None:
        """Match this frame's regions to the followed ones, grow their strokes."""
        free = [f for f in self._follows if t - f.last <= LOST]
        self._follows, self._regions = [], []
        for region in found:
            point, diameter = self._canvas(region)
            near = [
                (math.dist(f.predicted, point), n)
                for n, f in enumerate(free)
                if math.dist(f.predicted, point) <= max(diameter / 2 + f.step, 2 * unit)
            ]
            if near:
                follow = free.pop(min(near)[1])
                self._extend(follow, point, t, diameter, region.speed)
            elif (
                len(self._follows) + sum(f.stroke is not None for f in free) < self.spec.max_strokes
            ):
                follow = _Follow(point, t, diameter)
            else:  # as many followed as may be, strokes lost for a moment included
                continue
            self._follows.append(follow)
            self._regions.append(
                {
                    "center": list(point),
                    "radius": diameter / 2,
                    "speed": region.speed,
                    "stroke": follow.stroke,
                }
            )
        self._follows += [f for f in free if f.stroke is not None]

    def _extend(self, follow: _Follow, point, t: float, diameter: float, speed: float) -> None:
        """``follow`` seen again at ``point``: a stroke after 3 consecutive frames,
        its centre moving between them as fast as the flow says (within a factor
        :data:`AGREE`, or ``threshold``). A frame it jumped to (where the flow has
        not caught up with a fast small object yet, its centre lags, then jumps)
        starts the count again, as the first of the 3, as a new region's first
        frame does (the stroke's points are from the 2nd: the centre it jumped to
        is not one of them). A step under an eighth of the region's diameter always
        agrees: there the outline's noise is the centre's motion."""
        step, follow.step = math.dist(follow.point, point), math.dist(follow.point, point)
        moved = step / (t - follow.last)
        agree = (
            step <= diameter / 8
            or speed / AGREE <= moved <= AGREE * speed
            or abs(moved - speed) <= self.spec.threshold
        )
        follow.seen = [*follow.seen[-FRAMES:], (point, t, diameter)]
        if follow.stroke is None:
            if not agree:  # it starts again from this frame
                follow.seen = follow.seen[-1:]
            made = follow.seen[-FRAMES:]
            if len(made) == FRAMES and made[-2][0] != made[-1][0]:
                low, high = self.spec.width
                width = min(high, max(low, statistics.median(s[2] for s in made)))
                points = [p for p, _, _ in made[1:]]  # at the 2nd frame its stylus is
                times = [float(s[1]) for s in made[1:]]  # at rest: a take replays it
                self._begin(follow, _Stroke(points, times, round(width, DECIMALS), self.spec))
            return
        stroke = self._strokes[follow.stroke]
        if point == stroke.points[-1]:
            return
        if not stroke.room(point):
            stroke = _Stroke([stroke.points[-1]], [stroke.times[-1]], stroke.width, self.spec)
            self._begin(follow, stroke)
        stroke.add(point, float(t))

    def _begin(self, follow: _Follow, stroke: _Stroke) -> None:
        self._strokes.append(stroke)
        follow.stroke = len(self._strokes) - 1
        self._live.append(follow.stroke)
