"""Clips made in NumPy for the ``motion`` tests (the contract's cases): textured discs
moving over a still textured background, a still scene with sensor noise, a shaken
camera. Each :class:`MotionClip` holds its RGB frames, their times and, per disc, its
centre at every frame (frame coordinates: pixel centres at +0.5) and when it moves.

Everything is made from fixed seeds: the same call gives the same frames.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import cv2
import numpy as np

#: A path: seconds since the motion began -> (x, y) offset from where it began.
Path = Callable[[float], tuple[float, float]]


def texture(width: int, height: int, seed: int, grain: float = 2.0) -> np.ndarray:
    """An RGB texture: noise blurred by ``grain`` pixels plus a few slow waves, so that
    optical flow finds structure at every scale."""
    rng = np.random.default_rng(seed)
    noise = rng.normal(0.0, 1.0, (height, width, 3)).astype(np.float32)
    noise = cv2.GaussianBlur(noise, (0, 0), grain)
    noise *= 60.0 / max(float(noise.std()), 1e-6)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    phase = rng.uniform(0, 2 * math.pi, 3)
    waves = np.stack(
        [40 * np.sin(x / (23 + 7 * c) + y / (31 + 5 * c) + phase[c]) for c in range(3)], axis=-1
    )
    return np.clip(128 + noise + waves, 0, 255).astype(np.uint8)


@dataclass
class Disc:
    """A textured disc of diameter ``diameter`` at ``start`` (frame coordinates),
    moving along ``path`` from ``t0`` to ``t1`` seconds, still before and after."""

    diameter: float
    start: tuple[float, float]
    path: Path
    t0: float
    t1: float
    seed: int = 7

    def center(self, t: float) -> tuple[float, float]:
        dx, dy = self.path(min(max(t, self.t0), self.t1) - self.t0)
        return (self.start[0] + dx, self.start[1] + dy)


def line(speed: float, angle: float = 0.0) -> Path:
    """Along a straight line at ``speed`` px/s, ``angle`` degrees (y down)."""
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    return lambda t: (speed * t * c, speed * t * s)


def arc(speed: float, radius: float) -> Path:
    """Along a circle of ``radius`` px at ``speed`` px/s, starting at its top, clockwise
    on screen (the offset is from the start point)."""
    return lambda t: (
        radius * math.sin(speed * t / radius),
        radius * (1 - math.cos(speed * t / radius)),
    )


@dataclass
class MotionClip:
    """``frames`` (HxWx3 RGB uint8) at ``times`` seconds; ``discs`` the moving discs."""

    frames: list[np.ndarray]
    times: list[float]
    discs: list[Disc] = field(default_factory=list)

    def __iter__(self) -> Iterator[tuple[np.ndarray, float]]:
        return iter(zip(self.frames, self.times, strict=True))


def _paste(frame: np.ndarray, disc: Disc, skin: np.ndarray, t: float) -> None:
    """Draw ``disc`` at its place at ``t``, its texture ``skin`` moving with it (the
    disc's edge antialiased over one pixel)."""
    cx, cy = disc.center(t)
    r = disc.diameter / 2
    h, w = frame.shape[:2]
    x0, x1 = max(0, int(cx - r - 2)), min(w, int(cx + r + 3))
    y0, y1 = max(0, int(cy - r - 2)), min(h, int(cy + r + 3))
    if x1 <= x0 or y1 <= y0:
        return  # out of the frame
    y, x = np.mgrid[y0:y1, x0:x1].astype(np.float64) + 0.5
    cover = np.clip(r + 0.5 - np.hypot(x - cx, y - cy), 0.0, 1.0)[..., None]
    side = skin.shape[0]
    u = np.clip(np.floor(x - cx + side / 2).astype(int), 0, side - 1)
    v = np.clip(np.floor(y - cy + side / 2).astype(int), 0, side - 1)
    patch = frame[y0:y1, x0:x1].astype(np.float64)
    frame[y0:y1, x0:x1] = np.round(patch * (1 - cover) + skin[v, u] * cover).astype(np.uint8)


def disc_clip(
    discs: list[Disc],
    size: tuple[int, int] = (640, 360),
    seconds: float = 2.0,
    fps: float = 30.0,
    seed: int = 1,
) -> MotionClip:
    """``discs`` over a still textured background, ``seconds`` long at ``fps``."""
    w, h = size
    ground = texture(w, h, seed)
    skins = [texture(int(d.diameter) + 8, int(d.diameter) + 8, d.seed, grain=1.5) for d in discs]
    times = [n / fps for n in range(int(round(seconds * fps)))]
    frames = []
    for t in times:
        frame = ground.copy()
        for disc, skin in zip(discs, skins, strict=True):
            _paste(frame, disc, skin, t)
        frames.append(frame)
    return MotionClip(frames, times, list(discs))


def noise_clip(
    std: float = 4.0, size: tuple[int, int] = (640, 360), seconds: float = 2.0, fps: float = 30.0
) -> MotionClip:
    """A still textured scene with Gaussian sensor noise of ``std`` levels per frame."""
    w, h = size
    ground = texture(w, h, 3).astype(np.float32)
    rng = np.random.default_rng(11)
    times = [n / fps for n in range(int(round(seconds * fps)))]
    frames = [
        np.clip(np.round(ground + rng.normal(0.0, std, ground.shape)), 0, 255).astype(np.uint8)
        for _ in times
    ]
    return MotionClip(frames, times)


def shake_clip(
    amplitude: float = 4.0,
    size: tuple[int, int] = (640, 360),
    seconds: float = 2.0,
    fps: float = 30.0,
) -> MotionClip:
    """A shaken camera: the whole (textured) view moves by up to ``amplitude`` px a
    frame, in a random direction (a bounded random walk), new content entering at
    the edges."""
    w, h = size
    pad = int(amplitude * seconds * fps / 4) + 8
    ground = texture(w + 2 * pad, h + 2 * pad, 5)
    rng = np.random.default_rng(13)
    times = [n / fps for n in range(int(round(seconds * fps)))]
    x = y = 0.0
    frames = []
    for _ in times:
        frames.append(
            cv2.warpAffine(ground, np.float32([[1, 0, x - pad], [0, 1, y - pad]]), (w, h))
        )
        angle, step = rng.uniform(0, 2 * math.pi), rng.uniform(0.5, 1.0) * amplitude
        dx, dy = step * math.cos(angle), step * math.sin(angle)
        x = float(np.clip(x + dx, -pad + 2, pad - 2))
        y = float(np.clip(y + dy, -pad + 2, pad - 2))
    return MotionClip(frames, times)
