"""Generated sound for the signal tests: tones as 16-bit PCM, written as WAV
(Python's own ``wave``) or beside a video in Matroska (PyAV, PCM: lossless);
samples/pulse.json's beat and what its breathing drop should measure."""

from __future__ import annotations

import importlib.util
import math
import os
import wave
from fractions import Fraction
from pathlib import Path

import av
import numpy as np
from helpers import ROOT

from marblevideo.recipe import load_recipe
from marblevideo.signals import AudioSignals


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


# samples/pulse.json over its beat (samples/make_pulse_sound.py)

PULSE = ROOT / "samples" / "pulse.json"


BEAT_RATE = 22050


CORAL = (231, 111, 81)  # the inner breathing drop of pulse.json, radius 40..120


def _beat_module():
    spec = importlib.util.spec_from_file_location(
        "pulse_sound", ROOT / "samples" / "make_pulse_sound.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def beat_samples(seconds: float) -> np.ndarray:
    return pcm16([_beat_module().beat(seconds, BEAT_RATE)])


def coral_radius(rgba: np.ndarray, scale: float) -> float:
    """The radius (canvas units) of a disc of CORAL's area in ``rgba`` drawn at ``scale``."""
    near = np.abs(rgba[..., :3].astype(int) - CORAL).max(axis=-1) <= 24
    return math.sqrt(near.sum() / math.pi) / scale


def expected_radius(signals: AudioSignals, t: float) -> float:
    track = load_recipe(PULSE).ops[10].params["radius"]  # ring of 8, base, 2 breathing drops
    assert (track.lo, track.hi) == (40, 120)
    return track.lo + (track.hi - track.lo) * signals.at(track.signal, t)
