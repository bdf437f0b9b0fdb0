"""A clip for the motion benchmarks: six textured discs (diameter 140 px) on a 3 x 2
grid, each going round its own circle (radius 90 px, four laps in the clip, so a
looped clip has no seam: about 226 px/s), over a still textured background;
H.264 (CRF 18, yuv420p), made with PyAV and kept in the temporary folder.

    python -m benchmarks.motion_clip [--size 1280x720] [--seconds 10] [--out clip.mp4]
"""

from __future__ import annotations

import argparse
import math
import tempfile
from fractions import Fraction
from pathlib import Path

import numpy as np

DIAMETER = 140
RADIUS = 90  # of each disc's circle
LAPS = 4


def texture(width: int, height: int, seed: int) -> np.ndarray:
    """An RGB texture (blurred noise and slow waves) that optical flow can follow."""
    import cv2

    rng = np.random.default_rng(seed)
    noise = cv2.GaussianBlur(rng.normal(0, 1, (height, width, 3)).astype(np.float32), (0, 0), 2)
    noise *= 60 / max(float(noise.std()), 1e-6)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    waves = np.stack([40 * np.sin(x / (23 + 7 * c) + y / (31 + 5 * c)) for c in range(3)], -1)
    return np.clip(128 + noise + waves, 0, 255).astype(np.uint8)


def centres(size: tuple[int, int], t: float, seconds: float) -> list[tuple[float, float]]:
    """The six discs' centres at ``t`` (each its own phase and direction)."""
    w, h = size
    out = []
    for k in range(6):
        gx, gy = w * (1 + 2 * (k % 3)) / 6, h * (1 + 2 * (k // 3)) / 4
        angle = (-1) ** k * 2 * math.pi * LAPS * t / seconds + k
        out.append((gx + RADIUS * math.cos(angle), gy + RADIUS * math.sin(angle)))
    return out


def frame(ground, skin, size, t: float, seconds: float) -> np.ndarray:
    """The clip's RGB frame at ``t``."""
    img = ground.copy()
    r, side = DIAMETER / 2, skin.shape[0]
    for cx, cy in centres(size, t, seconds):
        x0, y0 = int(cx - r) - 1, int(cy - r) - 1
        y, x = np.mgrid[y0 : y0 + side, x0 : x0 + side].astype(np.float64) + 0.5
        cover = np.clip(r + 0.5 - np.hypot(x - cx, y - cy), 0, 1)[..., None]
        patch = img[y0 : y0 + side, x0 : x0 + side].astype(np.float64)
        img[y0 : y0 + side, x0 : x0 + side] = np.round(patch * (1 - cover) + skin * cover)
    return img


def six_discs(
    path: str | Path | None = None,
    size: tuple[int, int] = (1280, 720),
    seconds: float = 10.0,
    fps: int = 30,
) -> Path:
    """The clip at ``path`` (default: in the temporary folder, made once per size)."""
    import av

    w, h = size
    path = Path(
        path
        or Path(tempfile.gettempdir()) / f"marblevideo-six-discs-{w}x{h}-{seconds:g}s-{fps}.mp4"
    )
    if path.exists():
        return path
    ground = texture(w, h, 1)
    skin = texture(DIAMETER + 4, DIAMETER + 4, 7)
    tmp = path.with_name(f".{path.name}.tmp.mp4")
    with av.open(str(tmp), "w") as out:
        stream = out.add_stream("libx264", rate=fps)
        stream.width, stream.height, stream.pix_fmt = w, h, "yuv420p"
        stream.options = {"crf": "18", "preset": "veryfast"}
        stream.codec_context.time_base = Fraction(1, fps)
        for n in range(round(seconds * fps)):
            video = av.VideoFrame.from_ndarray(frame(ground, skin, size, n / fps, seconds), "rgb24")
            video.pts = n
            for packet in stream.encode(video):
                out.mux(packet)
        for packet in stream.encode():
            out.mux(packet)
    tmp.replace(path)
    return path


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size", default="1280x720")
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--out")
    args = p.parse_args()
    w, h = map(int, args.size.split("x"))
    print(six_discs(args.out, (w, h), args.seconds))


if __name__ == "__main__":
    main()
