"""Outputs that play everywhere: an MP4 or MOV gets AAC in place of the Opus,
FLAC or PCM it could hold but QuickTime and Safari do not play (a note says
so; ``--audio copy`` keeps the audio bit-exact), and ``--size W`` / ``--size
xH`` keep the input's aspect with even sides, as ffmpeg's ``scale=W:-2``."""

from __future__ import annotations

import subprocess
import sys

import av
import pytest
from clips import probe, write_clip
from helpers import ROOT, one_line, subprocess_env
from sound import pcm16, tone, write_video_with_sound

pytestmark = pytest.mark.tier("integration")

SWIRL = ROOT / "samples" / "swirl.json"
OPUS = ROOT / "samples" / "pulse.opus"


def marblevideo(*args, cwd) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "marblevideo", *map(str, args)]
    return subprocess.run(
        cmd, cwd=cwd, env=subprocess_env(), capture_output=True, text=True, timeout=300
    )


def audio_packets(path, limit: int = 20) -> tuple[str, list[bytes]]:
    with av.open(str(path)) as container:
        stream = container.streams.audio[0]
        packets = [bytes(p) for p in container.demux(stream) if p.size][:limit]
        return stream.codec_context.name, packets


def test_opus_in_an_mp4_becomes_aac_with_a_note_and_copy_keeps_it_bit_exact(tmp_path):
    clip = write_clip(tmp_path / "clip.mp4", frames=10, audio=False)
    args = [clip, "--ops", SWIRL, "--soundtrack", OPUS, "-o"]
    auto = marblevideo(*args, "auto.mp4", cwd=tmp_path)
    assert auto.returncode == 0, auto.stderr
    assert "opus audio in" in auto.stderr and "--audio copy keeps it" in auto.stderr
    assert probe(tmp_path / "auto.mp4").audio_codec == "aac"
    copy = marblevideo(*args, "copy.mp4", "--audio", "copy", cwd=tmp_path)
    assert copy.returncode == 0, copy.stderr
    codec, packets = audio_packets(tmp_path / "copy.mp4")
    assert codec == "opus"
    source = audio_packets(OPUS, 10_000)[1]
    start = source.index(packets[0])  # as much of the soundtrack as the clip lasts
    assert packets == source[start : start + len(packets)]
    kept = marblevideo(*args, "auto.mkv", cwd=tmp_path)  # Matroska plays Opus: copied
    assert kept.returncode == 0, kept.stderr
    assert audio_packets(tmp_path / "auto.mkv")[0] == "opus"


def test_pcm_in_a_mov_becomes_aac(tmp_path):
    samples = pcm16([tone(440, 1.0, 48000, 0.3)])
    clip = write_video_with_sound(tmp_path / "pcm.mkv", samples, 48000, frames=10)
    proc = marblevideo(clip, "--ops", SWIRL, "-o", "out.mov", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "pcm_s16le audio in" in proc.stderr
    assert probe(tmp_path / "out.mov").audio_codec == "aac"


@pytest.mark.parametrize(
    ("size", "expected"),
    [("100", (100, 56)), ("x50", (88, 50)), ("1600", (1600, 900)), ("80x80", (80, 80))],
)
def test_one_side_keeps_the_aspect_with_even_sides(tmp_path, size, expected):
    clip = write_clip(tmp_path / "clip.mp4", size=(480, 270), frames=3, audio=False)
    proc = marblevideo(clip, "--ops", SWIRL, "-o", "out.mp4", "--size", size, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    got = probe(tmp_path / "out.mp4")
    assert (got.width, got.height) == expected
    assert "padded" not in proc.stderr


def test_one_side_of_a_still(tmp_path):
    proc = marblevideo(
        ROOT / "samples" / "coffee.jpg",
        "--ops",
        SWIRL,
        "-o",
        "o.png",
        "--size",
        "x100",
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    import cv2

    image = cv2.imread(str(tmp_path / "o.png"))
    natural = cv2.imread(str(ROOT / "samples" / "coffee.jpg"))
    assert image.shape[0] == 100
    assert image.shape[1] == max(2, round(100 * natural.shape[1] / natural.shape[0] / 2) * 2)


@pytest.mark.parametrize(
    ("args", "fault"),
    [
        (["--size", "300"], "a blank sheet has no aspect to keep"),
        (["--size", "x0"], "each side must be"),
    ],
)
def test_one_side_refused_is_one_line(tmp_path, args, fault):
    proc = marblevideo("--ops", SWIRL, "-o", "o.png", *args, cwd=tmp_path)
    assert proc.returncode == 2
    assert fault in one_line(proc)
