"""Write samples/pulse.opus: 8 s of a 120 bpm beat to render samples/pulse.json against.

A kick (a sine falling from 120 to 50 Hz) on every beat, a hi-hat (a short burst
of differentiated noise: mostly above 4 kHz) half-way between, and a quiet chord
under both; mono, 48 kHz, Opus at 32 kbit/s (about 30 KB). Run from the
repository root: ``python samples/make_pulse_sound.py [SECONDS]``; the tests
make theirs with :func:`beat`.
"""

import sys
from pathlib import Path

import av
import numpy as np

HERE = Path(__file__).resolve().parent
RATE, BPM = 48000, 120


def beat(seconds: float, rate: int = RATE, bpm: float = BPM) -> np.ndarray:
    """The beat as float64 samples in -1..1 (kick on each beat from t = 0)."""
    n = round(seconds * rate)
    t = np.arange(n) / rate
    period = 60.0 / bpm
    out = 0.04 * (np.sin(2 * np.pi * 220 * t) + np.sin(2 * np.pi * 330 * t))
    since = t % period  # seconds since the last kick
    sweep = 50 + 70 * np.exp(-since / 0.04)  # Hz, falling from 120 to 50
    phase = 2 * np.pi * np.cumsum(sweep) / rate
    onset = np.arange(n) - (since * rate).astype(int)  # the sample of the last kick
    out += 0.8 * np.exp(-since / 0.1) * np.sin(phase - phase[onset])
    noise = np.diff(np.random.default_rng(7).uniform(-1, 1, n + 1))  # white, tilted high
    hat = (t - period / 2) % period
    out += 0.3 * np.exp(-hat / 0.02) * noise
    return np.clip(out, -1, 1)


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 8.0
    samples = beat(seconds).astype(np.float32)[None]
    target = HERE / "pulse.opus"
    with av.open(str(target), "w", format="ogg") as out:
        stream = out.add_stream("libopus", rate=RATE, layout="mono")
        stream.bit_rate = 32000
        for at in range(0, samples.shape[1], 960):
            frame = av.AudioFrame.from_ndarray(samples[:, at : at + 960], "flt", "mono")
            frame.sample_rate, frame.pts = RATE, at
            out.mux(stream.encode(frame))
        out.mux(stream.encode(None))
    print(f"wrote {target}: {seconds:g} s, {target.stat().st_size // 1024} KB")


if __name__ == "__main__":
    main()
