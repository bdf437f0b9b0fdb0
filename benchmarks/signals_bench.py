"""The audio analysis (marblevideo.signals): streamed in blocks against the same
analysis of the whole stream decoded into memory first, side by side in one run.

Writes a WAV of MINUTES minutes of 48 kHz stereo noise with a beat (in a
temporary folder), then, in alternating rounds, times both and measures the
peak of what NumPy and Python allocate (tracemalloc) during each. Both give the
same levels (checked). Run from the repository root:
``python -m benchmarks.signals_bench [MINUTES] [ROUNDS]``.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
import tracemalloc
import wave
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

from marblevideo.signals.audio import analyse_stream, blocks
from marblevideo.signals.bands import BANDS, FilterBank
from marblevideo.signals.levels import Slots

RATE = 48000


def write_sound(path: Path, minutes: float) -> None:
    """Stereo noise under a 2 Hz kick, written a second at a time."""
    rng = np.random.default_rng(1)
    with wave.open(str(path), "wb") as out:
        out.setnchannels(2)
        out.setsampwidth(2)
        out.setframerate(RATE)
        t = np.arange(RATE) / RATE
        kick = np.sin(2 * np.pi * 60 * t) * np.exp(-(t % 0.5) / 0.1)
        for _ in range(round(minutes * 60)):
            left = 0.1 * rng.uniform(-1, 1, RATE) + 0.6 * kick
            data = np.stack([left, left[::-1]], axis=1)
            out.writeframes((data * 32767).astype(np.int16).tobytes())


def streamed(path: Path):
    with av.open(str(path)) as container:
        return analyse_stream(container, Fraction(0)).rms


def whole(path: Path):
    """The baseline: every sample decoded into one array, then the same analysis."""
    with av.open(str(path)) as container:
        x = np.concatenate(list(blocks(container, container.streams.audio[0])))
    slots = Slots(RATE, Fraction(0), BANDS)
    slots.add(FilterBank(RATE)(x))
    return slots.rms()


def measure(fn, path: Path) -> tuple[float, float, dict]:
    tracemalloc.start()
    began = time.perf_counter()
    out = fn(path)
    seconds = time.perf_counter() - began
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return seconds, peak, out


def main() -> None:
    minutes = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "sound.wav"
        write_sound(path, minutes)
        results: dict[str, list[tuple[float, float]]] = {"streamed": [], "whole": []}
        for _ in range(rounds):
            outs = {}
            for name, fn in (("streamed", streamed), ("whole", whole)):
                seconds, peak, outs[name] = measure(fn, path)
                results[name].append((seconds, peak))
            for band in BANDS:
                np.testing.assert_allclose(outs["streamed"][band], outs["whole"][band], rtol=1e-9)
    audio = minutes * 60
    print(f"{minutes:g} min of 48 kHz stereo, {rounds} rounds, medians (best in brackets)")
    print("| analysis | seconds | x real time | peak MB allocated |")
    print("|---|---|---|---|")
    for name, rows in results.items():
        times, peaks = [r[0] for r in rows], [r[1] for r in rows]
        med = statistics.median(times)
        print(
            f"| {name} | {med:.2f} ({min(times):.2f}) | {audio / med:.0f}x "
            f"| {statistics.median(peaks):.0f} |"
        )


if __name__ == "__main__":
    main()
