"""Small test clips written with PyAV, and a probe that reads back what tests compare.

Every frame carries a white 8x8 marker in its top-left corner (so rotation is
visible) on a background whose green level is ``8 * index`` (so frames differ).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

AUDIO_RATE = 44100


def picture(index: int, width: int, height: int) -> np.ndarray:
    """RGB frame ``index``: marker top-left, red ramp left to right, green = 8 * index."""
    img = np.zeros((height, width, 3), np.uint8)
    img[:, :, 0] = np.linspace(0, 160, width, dtype=np.uint8)[None, :]
    img[:, :, 1] = (8 * index) % 256
    img[:8, :8] = 255
    return img


def write_clip(
    path: str | os.PathLike,
    *,
    size: tuple[int, int] = (96, 64),
    frames: int = 25,
    fps: int = 25,
    pts: list[int] | None = None,
    time_base: Fraction | None = None,
    codec: str = "libx264",
    audio: bool = True,
    audio_seconds: float | None = None,
    rotation: int | None = None,
    corrupt_at: int | None = None,
    color_range: int | None = None,
    encoder: dict[str, str] | None = None,
) -> Path:
    """Write a clip: ``frames`` frames at ``fps`` (or at explicit ``pts`` in ``time_base``),
    optional mono AAC sine audio, a colour range (2: full), a display rotation (degrees
    counter-clockwise), the ``corrupt_at``-th video packet replaced by random bytes, and
    ``encoder`` options (default x264's ultrafast preset, which makes no B-frames)."""
    width, height = size
    time_base = time_base or Fraction(1, fps)
    pts = pts if pts is not None else [round(i / fps / time_base) for i in range(frames)]
    with av.open(str(path), "w") as out:
        video = out.add_stream(codec, rate=fps)
        video.width, video.height = width, height
        video.pix_fmt = "yuvj420p" if codec == "mjpeg" else "yuv420p"
        video.time_base = video.codec_context.time_base = time_base
        if encoder is None:
            encoder = {"preset": "ultrafast"} if codec == "libx264" else {}
        video.codec_context.options = encoder
        if color_range:
            video.codec_context.color_range = color_range
        if rotation is not None:
            video.set_display_rotation(rotation)
        sound = out.add_stream("aac", rate=AUDIO_RATE, layout="mono") if audio else None
        written = 0
        for index, stamp in enumerate(pts):
            frame = av.VideoFrame.from_ndarray(picture(index, width, height), format="rgb24")
            if color_range:
                frame = frame.reformat(format=video.pix_fmt, dst_color_range=color_range)
                frame.color_range = color_range
            frame.pts, frame.time_base = stamp, time_base
            for packet in video.encode(frame):
                if written == corrupt_at:
                    packet = _garbage(packet, video)
                written += 1
                out.mux(packet)
        out.mux(video.encode(None))
        if sound is not None:
            seconds = audio_seconds or float((pts[-1] + pts[1] - pts[0]) * time_base)
            count = int(seconds * AUDIO_RATE)
            wave = 0.3 * np.sin(2 * np.pi * 440 * np.arange(count) / AUDIO_RATE)
            wave = wave.astype(np.float32)[None]
            for at in range(0, count, 1024):
                chunk = av.AudioFrame.from_ndarray(wave[:, at : at + 1024], "fltp", "mono")
                chunk.sample_rate, chunk.pts = AUDIO_RATE, at
                out.mux(sound.encode(chunk))
            out.mux(sound.encode(None))
    return Path(path)


def _garbage(packet: av.Packet, stream) -> av.Packet:
    bad = av.Packet(np.random.default_rng(1).integers(0, 256, packet.size, np.uint8).tobytes())
    bad.pts, bad.dts, bad.time_base = packet.pts, packet.dts, packet.time_base
    bad.stream = stream
    return bad


@dataclass
class Probe:
    codec: str
    pix_fmt: str
    width: int
    height: int
    time_base: Fraction
    pts: list[int]  # decoded video frames, in order
    times: list[float]  # the same in seconds
    rotation: int
    color_range: int
    audio_codec: str | None
    audio_packets: list[bytes]
    audio_times: list[float]
    duration: float | None  # container duration, seconds
    frames: list[np.ndarray] = field(repr=False)  # RGB, as stored (not rotated)


def probe(path: str | os.PathLike) -> Probe:
    """Decode a whole file (small clips only)."""
    with av.open(str(path)) as container:
        video = container.streams.video[0]
        audio = container.streams.audio[0] if container.streams.audio else None
        pts, times, frames, rotation, color_range = [], [], [], 0, 0
        packets, audio_times = [], []
        for packet in container.demux():
            if packet.stream.type == "audio":
                if packet.size:
                    packets.append(bytes(packet))
                    audio_times.append(float(packet.pts * packet.time_base))
                continue
            for frame in packet.decode():
                pts.append(frame.pts)
                times.append(float(frame.time))
                frames.append(frame.to_ndarray(format="rgb24"))
                rotation, color_range = frame.rotation, frame.color_range
        return Probe(
            codec=video.codec_context.name,
            pix_fmt=video.codec_context.pix_fmt,
            width=video.codec_context.width,
            height=video.codec_context.height,
            time_base=video.time_base,
            pts=pts,
            times=times,
            rotation=rotation,
            color_range=int(color_range),
            frames=frames,
            audio_codec=audio.codec_context.name if audio else None,
            audio_packets=packets,
            audio_times=audio_times,
            duration=container.duration / av.time_base if container.duration else None,
        )


def write_vfr_clip(path: str | os.PathLike, frames: int = 48) -> Path:
    """A clip with B-frames (x264 medium, up to 3) at a variable frame rate (steps
    of 40-42 ms with a 95-97 ms gap every fifth frame, time base 1/1000), a
    keyframe at least every 12 frames, and AAC audio."""
    pts, t = [], 0
    for i in range(frames):
        pts.append(t)
        t += (40 if i % 5 else 95) + i % 3
    return write_clip(
        path,
        pts=pts,
        time_base=Fraction(1, 1000),
        encoder={"preset": "medium", "g": "12", "bf": "3"},
    )
