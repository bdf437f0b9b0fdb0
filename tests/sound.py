"""Generated sound for the signal tests: tones as 16-bit PCM, written as WAV
(Python's own ``wave``) or beside a video in Matroska (PyAV, PCM: lossless)."""

from __future__ import annotations

import os
import wave
from fractions import Fraction
from pathlib import Path

import av
import numpy as np


def tone(freq: float, seconds: float, rate: int, amplitude: float, start: float = 0.0):
    """A sine of ``freq`` Hz, float64, beginning at phase 0 at ``start`` seconds."""
    t = start + np.arange(round(seconds * rate)) / rate
    return amplitude * np.sin(2 * np.pi * freq * t)


def pcm16(channels: list[np.ndarray]) -> np.ndarray:
    """Float channels (-1..1) as int16 samples, (n, channels)."""
    data = np.stack(channels, axis=1)
    return np.clip(np.round(data * 32767), -32768, 32767).astype(np.int16)


def write_wav(path: str | os.PathLike, samples: np.ndarray, rate: int) -> Path:
    """int16 samples (n, channels) as a WAV file."""
    with wave.open(str(path), "wb") as out:
        out.setnchannels(samples.shape[1])
        out.setsampwidth(2)
        out.setframerate(rate)
        out.writeframes(samples.tobytes())
    return Path(path)


def write_video_with_sound(
    path: str | os.PathLike,
    samples: np.ndarray,
    rate: int,
    *,
    audio_start: Fraction = Fraction(0),
    frames: int = 25,
    fps: int = 25,
    size: tuple[int, int] = (64, 48),
) -> Path:
    """A Matroska clip: ``frames`` grey frames from t = 0 and int16 ``samples``
    (n, channels) as PCM whose first sample lies at ``audio_start`` seconds."""
    layout = "mono" if samples.shape[1] == 1 else "stereo"
    with av.open(str(path), "w", format="matroska") as out:
        video = out.add_stream("ffv1", rate=fps)
        video.width, video.height, video.pix_fmt = *size, "yuv420p"
        sound = out.add_stream("pcm_s16le", rate=rate, layout=layout)
        for i in range(frames):
            frame = av.VideoFrame.from_ndarray(np.full((*size[::-1], 3), 8 * i % 256, np.uint8))
            frame.pts, frame.time_base = i, Fraction(1, fps)
            out.mux(video.encode(frame))
        out.mux(video.encode(None))
        offset = round(audio_start * rate)
        for at in range(0, len(samples), 1024):
            chunk = np.ascontiguousarray(samples[at : at + 1024]).reshape(1, -1)
            frame = av.AudioFrame.from_ndarray(chunk, "s16", layout)
            frame.sample_rate, frame.pts, frame.time_base = rate, offset + at, Fraction(1, rate)
            out.mux(sound.encode(frame))
        out.mux(sound.encode(None))
    return Path(path)
