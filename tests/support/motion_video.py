"""A :class:`~motion_clips.MotionClip` encoded as a video file (PyAV, H.264 at a
high quality), for the live sessions and renders that read files."""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import av


def encode_clip(clip, path: str | os.PathLike, fps: int = 30) -> Path:
    """Write ``clip``'s frames to ``path`` (H.264, yuv420p, CRF 12) at ``fps``
    (their times are n / fps); the path."""
    path = Path(path)
    h, w = clip.frames[0].shape[:2]
    with av.open(str(path), "w") as out:
        stream = out.add_stream("libx264", rate=fps)
        stream.width, stream.height, stream.pix_fmt = w, h, "yuv420p"
        stream.options = {"crf": "12", "preset": "veryfast"}
        stream.codec_context.time_base = Fraction(1, fps)
        for n, rgb in enumerate(clip.frames):
            frame = av.VideoFrame.from_ndarray(rgb, format="rgb24")
            frame.pts = n
            for packet in stream.encode(frame):
                out.mux(packet)
        for packet in stream.encode():
            out.mux(packet)
    return path
