"""The audio analysis against an independent float64 transcription of the
contract ("Signals"), written here as plain per-sample loops, on generated tones:
every band, the dB map, attack and release, a stream starting after the video,
block boundaries."""

from __future__ import annotations

import math
from fractions import Fraction

import av
import numpy as np
import pytest
from sound import pcm16, tone, write_video_with_sound, write_wav

from marblevideo.recipe.signals import Signal
from marblevideo.signals import AudioSignals, analyse
from marblevideo.signals.audio import analyse_stream, stream_offset
from marblevideo.signals.levels import Slots

pytestmark = pytest.mark.tier("fast")

RATE = 16000
COOKBOOK = {  # band: (kind, f0, Q)
    "low": ("lowpass", 150.0, 1 / math.sqrt(2)),
    "mid": ("bandpass", 1000.0, 0.7),
    "high": ("highpass", 4000.0, 1 / math.sqrt(2)),
}


# ---------------------------------------------------------------- the contract, by hand


def ref_band(x: list[float], band: str, sr: int) -> list[float]:
    """The band of x: the cookbook biquad run sample by sample from a zero state."""
    if band == "level":
        return list(x)
    kind, f0, q = COOKBOOK[band]
    w0 = 2 * math.pi * f0 / sr
    alpha = math.sin(w0) / (2 * q)
    cos = math.cos(w0)
    b = {
        "lowpass": ((1 - cos) / 2, 1 - cos, (1 - cos) / 2),
        "highpass": ((1 + cos) / 2, -(1 + cos), (1 + cos) / 2),
        "bandpass": (alpha, 0.0, -alpha),
    }[kind]
    a0, a1, a2 = 1 + alpha, -2 * cos, 1 - alpha
    y: list[float] = []
    x1 = x2 = y1 = y2 = 0.0
    for xj in x:
        yj = (b[0] * xj + b[1] * x1 + b[2] * x2 - a1 * y1 - a2 * y2) / a0
        y.append(yj)
        x1, x2, y1, y2 = xj, x1, yj, y1
    return y


def ref_rms(y: list[float], sr: int, a0: Fraction, grid: int) -> list[float]:
    """r_i for i < grid: RMS of the samples at times a0 + j/sr in [i/100 - 0.05, i/100).
    Sample j is in window i exactly when 100 t < i <= 100 t + 5 (exact rationals)."""
    sums, counts = [0.0] * grid, [0] * grid
    for j, value in enumerate(y):
        t100 = (a0 + Fraction(j, sr)) * 100
        for i in range(math.floor(t100) + 1, math.floor(t100 + 5) + 1):
            if 0 <= i < grid:
                sums[i] += value * value
                counts[i] += 1
    return [math.sqrt(s / n) if n else 0.0 for s, n in zip(sums, counts, strict=True)]


def ref_levels(r: list[float], d0: float, d1: float) -> list[float]:
    return [min(max((20 * math.log10(max(ri, 1e-10)) - d0) / (d1 - d0), 0.0), 1.0) for ri in r]


def ref_envelope(v: list[float], attack: float, release: float) -> list[float]:
    out, e = [], 0.0
    for vi in v:
        tau = attack if vi > e else release
        c = 1.0 if tau == 0 else 1 - math.exp(-0.01 / tau)
        e = e + c * (vi - e)
        out.append(e)
    return out


def ref_mono(samples: np.ndarray) -> list[float]:
    """int16 (n, channels) as the mean of the channels in -1..1."""
    return [sum(int(c) / 32768 for c in row) / len(row) for row in samples]


# ---------------------------------------------------------------- sounds


def three_tones() -> np.ndarray:
    """Stereo, 1.2 s: 0-0.4 s a 100 Hz tone (left) under a quiet 1 kHz (right),
    0.4-0.8 s 1 kHz, 0.8-1.2 s 6 kHz, each band loud in its own part."""
    left = np.concatenate(
        [tone(100, 0.4, RATE, 0.6), tone(1000, 0.4, RATE, 0.3), tone(6000, 0.4, RATE, 0.4)]
    )
    right = np.concatenate(
        [tone(1000, 0.4, RATE, 0.02), tone(1000, 0.4, RATE, 0.3), np.zeros(round(0.4 * RATE))]
    )
    return pcm16([left, right])


@pytest.fixture(scope="module")
def tones_wav(tmp_path_factory):
    return write_wav(tmp_path_factory.mktemp("sound") / "tones.wav", three_tones(), RATE)


@pytest.fixture(scope="module")
def reference():
    """Every band's r_i of three_tones() at a0 = 0 and at a0 = 0.25 s."""
    x = ref_mono(three_tones())
    bands = {band: ref_band(x, band, RATE) for band in ("level", "low", "mid", "high")}
    return {
        a0: {band: ref_rms(y, RATE, a0, 160) for band, y in bands.items()}
        for a0 in (Fraction(0), Fraction(1, 4))
    }


# ---------------------------------------------------------------- the tests


@pytest.mark.parametrize("band", ["level", "low", "mid", "high"])
def test_every_band_matches_the_contract(tones_wav, reference, band):
    got = analyse(tones_wav, own=False).rms[band]
    want = reference[Fraction(0)][band]
    assert len(got) == 125  # windows up to the last sample's (1.2 s + 0.05 s)
    np.testing.assert_allclose(got, want[: len(got)], rtol=1e-9, atol=1e-12)
    assert not any(want[len(got) :])


def test_each_band_hears_its_own_tone(tones_wav):
    rms = analyse(tones_wav, own=False).rms
    parts = {name: slice(5 + 40 * k, 40 * (k + 1)) for k, name in enumerate(("low", "mid", "high"))}
    for band, part in parts.items():
        loud = rms[band][part].mean()
        others = [rms[band][p].mean() for name, p in parts.items() if name != band]
        assert loud > 4 * max(others), (band, loud, others)


def test_block_boundaries_change_nothing(tones_wav, reference):
    with av.open(str(tones_wav)) as container:
        small = analyse_stream(container, Fraction(0), size=777)
    for band, want in reference[Fraction(0)].items():
        np.testing.assert_allclose(small.rms[band], want[:125], rtol=1e-9, atol=1e-12)


def test_a_stream_starting_after_the_video(tmp_path, reference):
    clip = write_video_with_sound(
        tmp_path / "late.mkv", three_tones(), RATE, audio_start=Fraction(1, 4)
    )
    with av.open(str(clip)) as container:
        assert stream_offset(container) == Fraction(1, 4)
    analysis = analyse(clip, own=True)
    assert analysis.a0 == 0.25
    for band, want in reference[Fraction(1, 4)].items():
        np.testing.assert_allclose(analysis.rms[band], want[:150], rtol=1e-9, atol=1e-12)
    assert not any(analysis.rms["level"][:25])  # nothing heard before 0.25 s
    # the same file as a soundtrack: its first sample at t = 0
    np.testing.assert_allclose(
        analyse(clip, own=False).rms["low"], reference[Fraction(0)]["low"][:125], rtol=1e-9
    )


@pytest.mark.parametrize("a0", [Fraction(-13, 100), Fraction(1, 3), Fraction(7, 48000)])
def test_slots_place_every_sample_exactly(a0):
    """Offsets that put window edges between samples, on samples, and a stream
    starting before the video (its earlier samples still run the filters)."""
    rng = np.random.default_rng(3)
    y = rng.normal(0, 0.3, 5000)
    slots = Slots(RATE, a0, ("level",))
    for cut in (0, 1, 333, 334, 2000, 4999):  # uneven blocks, one of a single sample
        nxt = {0: 1, 1: 333, 333: 334, 334: 2000, 2000: 4999, 4999: 5000}[cut]
        slots.add({"level": y[cut:nxt]})
    got = slots.rms()["level"]
    want = ref_rms(list(y), RATE, a0, len(got) + 3)
    np.testing.assert_allclose(got, want[: len(got)], rtol=1e-9, atol=1e-12)
    assert not any(want[len(got) :])


@pytest.mark.parametrize(
    ("db", "attack", "release"),
    [
        ((-60.0, 0.0), 0.0, 0.0),
        ((-30.0, -6.0), 0.0, 0.0),
        ((-40.0, 0.0), 0.05, 0.3),
        ((-60.0, -10.0), 0.2, 0.0),
    ],
)
def test_the_signal_is_the_envelope_of_the_db_map(tones_wav, reference, db, attack, release):
    signals = AudioSignals(analyse(tones_wav, own=False))
    for band in ("low", "high"):
        r = reference[Fraction(0)][band]
        e = ref_envelope(ref_levels(r, *db), attack, release)
        signal = Signal(f"audio.{band}", db=db, attack=attack, release=release)
        for i in (0, 3, 17, 39, 40, 41, 80, 99, 124, 125, 140, 159):
            # t at the grid step, and just before the next one
            assert signals.at(signal, i / 100) == pytest.approx(e[i], abs=1e-9), (band, i)
            assert signals.at(signal, (i + 0.99) / 100) == pytest.approx(e[i], abs=1e-9)


def test_attack_and_release_shape_a_beat(tmp_path):
    """A 60 Hz burst from 0.2 to 0.5 s: the envelope rises with attack and falls with
    release, as the contract's recursion says, and far past the end of the file."""
    burst = np.concatenate([np.zeros(3200), tone(60, 0.3, RATE, 0.8), np.zeros(8000)])
    path = write_wav(tmp_path / "beat.wav", pcm16([burst]), RATE)
    signals = AudioSignals(analyse(path, own=False))
    r = ref_rms(ref_band(ref_mono(pcm16([burst])), "low", RATE), RATE, Fraction(0), 400)
    e = ref_envelope(ref_levels(r, -50.0, 0.0), 0.05, 0.4)
    slow = Signal("audio.low", db=(-50.0, 0.0), attack=0.05, release=0.4)
    got = [signals.at(slow, i / 100) for i in range(400)]
    np.testing.assert_allclose(got, e, atol=1e-9)
    assert got[20] < 0.1 < got[30] and got[49] > 0.7  # rises after the burst begins
    assert got[60] > 0.5 > got[150] > got[300] > 0  # falls slowly after it
    fast = Signal("audio.low", db=(-50.0, 0.0))
    assert signals.at(fast, 0.3) > 0.8 and signals.at(fast, 0.6) == 0.0
