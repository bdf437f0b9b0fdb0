"""Video I/O on real files: PyAV encodes and decodes, nothing mocked."""

from __future__ import annotations

import queue
import signal
import subprocess
import sys
import textwrap
import time
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from clips import picture, probe, write_clip
from helpers import subprocess_env
from tolerances import LOSSY_MEAN, LOSSY_MEAN_RESAMPLED

from marblevideo.errors import MediaError, OutputExistsError, UsageError
from marblevideo.jobs.pipeline import iter_frames, render_sheet, transcode
from marblevideo.jobs.stages import Stages, Stopped
from marblevideo.media.progress import Progress
from marblevideo.media.video import QUEUE_FRAMES, VideoOptions

pytestmark = pytest.mark.tier("fast")


def invert(rgba: np.ndarray, t: float) -> np.ndarray:
    out = 255 - rgba
    out[..., 3] = 255
    return out


class Recorder:
    """Identity transform that records what it was given."""

    def __init__(self):
        self.times: list[float] = []
        self.shapes: list[tuple[int, ...]] = []
        self.first: np.ndarray | None = None

    def __call__(self, rgba: np.ndarray, t: float) -> np.ndarray:
        assert rgba.flags.c_contiguous and rgba.dtype == np.uint8 and rgba.shape[2] == 4
        if self.first is None:
            self.first = rgba.copy()
        self.times.append(t)
        self.shapes.append(rgba.shape)
        return rgba


def quiet(**kw) -> VideoOptions:
    notes: list[str] = kw.pop("notes", [])
    return VideoOptions(progress="off", notify=notes.append, **kw)


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if ".part" in p.name)


@pytest.fixture(scope="module")
def cfr(tmp_path_factory) -> Path:
    """25 frames at 25 fps, 96x64, H.264 + AAC in MP4."""
    return write_clip(tmp_path_factory.mktemp("clips") / "cfr.mp4")


# ---------------------------------------------------------------------------- timing and audio


def test_cfr_timing_and_audio_copied_bit_exact(cfr, tmp_path):
    dst = tmp_path / "out.mp4"
    stats = transcode(cfr, dst, invert, quiet())
    src, out = probe(cfr), probe(dst)
    assert stats.frames == len(src.pts) == len(out.pts) == 25
    assert out.time_base == src.time_base
    assert out.pts == src.pts and out.times == src.times
    assert out.audio_packets == src.audio_packets and len(out.audio_packets) > 40
    assert out.audio_times == src.audio_times
    assert out.duration == pytest.approx(src.duration, abs=1e-3)
    assert stats.audio == "copy" and stats.audio_packets == len(src.audio_packets)
    assert stats.duration == pytest.approx(1.0)  # 25 frames of 1/25 s
    assert stats.summary("out.mp4").startswith("wrote out.mp4: 25 frames, 1.00 s, 96x64, ")
    # the picture is the inverted input (lossy codec: loose tolerance)
    diff = np.abs(out.frames[5].astype(int) - (255 - src.frames[5].astype(int)))
    assert diff.mean() < LOSSY_MEAN


def test_vfr_timestamps_kept(tmp_path):
    pts = [0, 40, 70, 150, 160, 300, 310, 320, 500, 650, 660, 900]
    src = write_clip(tmp_path / "vfr.mkv", pts=pts, time_base=Fraction(1, 1000), audio=False)
    dst = tmp_path / "out.mkv"
    transcode(src, dst, invert, quiet())
    assert probe(src).pts == pts
    assert probe(dst).pts == pts


def test_vfr_mp4_time_base_kept(tmp_path):
    pts = [0, 333, 1000, 1100, 2900, 3000, 4567]
    src = write_clip(tmp_path / "vfr.mp4", pts=pts, time_base=Fraction(1, 10000), audio=False)
    dst = tmp_path / "out.mp4"
    transcode(src, dst, invert, quiet())
    out = probe(dst)
    assert out.time_base == probe(src).time_base
    assert out.pts == probe(src).pts


def test_transform_gets_input_clock(cfr, tmp_path):
    rec = Recorder()
    transcode(cfr, tmp_path / "out.mp4", rec, quiet())
    assert rec.times == pytest.approx([i / 25 for i in range(25)], abs=1e-9)
    assert rec.shapes == [(64, 96, 4)] * 25


def test_time_dependent_transform_lands_on_its_frame(cfr, tmp_path):
    def shift(rgba, t):  # roll right by 10 px per second: frame i by round(i * 0.4)
        return np.ascontiguousarray(np.roll(rgba, round(t * 10), axis=1))

    dst = tmp_path / "out.mp4"
    transcode(cfr, dst, shift, quiet())
    frames = probe(dst).frames
    for i in (0, 12, 24):  # the white marker moved by round(i / 25 * 10)
        row = frames[i][4, :, 2].astype(int)  # blue: only the marker has it
        assert int(np.argmax(row > 128)) == round(i / 25 * 10)


# ---------------------------------------------------------------------------- the picture


def test_odd_size_padded_with_notice(tmp_path):
    src = write_clip(tmp_path / "odd.mkv", size=(64, 48), audio=False, frames=5)

    def crop(rgba, t):
        return np.ascontiguousarray(rgba[:47, :63])

    notes: list[str] = []
    stats = transcode(src, tmp_path / "out.mp4", crop, quiet(notes=notes))
    out = probe(tmp_path / "out.mp4")
    assert (out.width, out.height) == (64, 48) == stats.size
    assert notes == ["63x47 padded to 64x48 (edge pixels repeated): yuv420p needs even sizes"]


def test_size_option_and_other_output_size(cfr, tmp_path):
    def half(rgba, t):
        return np.ascontiguousarray(rgba[::2, ::2])

    transcode(cfr, tmp_path / "out.mkv", half, quiet(size=(48, 32)))
    assert (probe(tmp_path / "out.mkv").width, probe(tmp_path / "out.mkv").height) == (48, 32)
    with pytest.raises(ValueError, match="size option"):
        transcode(cfr, tmp_path / "bad.mkv", half, quiet(size=(96, 64)))
    assert leftovers(tmp_path) == [] and not (tmp_path / "bad.mkv").exists()


@pytest.mark.parametrize("rotation", [90, -90, 180])
def test_rotation_upright(tmp_path, rotation):
    src = write_clip(tmp_path / "phone.mp4", size=(64, 48), rotation=rotation, audio=False)
    assert probe(src).rotation % 360 == rotation % 360
    rec, notes = Recorder(), []
    dst = tmp_path / "out.mp4"
    transcode(src, dst, rec, quiet(notes=notes))
    # expected: the stored picture turned counter-clockwise by `rotation`
    expected = np.rot90(picture(0, 64, 48), rotation // 90)
    assert rec.first.shape[:2] == expected.shape[:2]
    assert np.abs(rec.first[..., :3].astype(int) - expected).mean() < LOSSY_MEAN_RESAMPLED
    out = probe(dst)
    assert out.rotation == 0 and (out.height, out.width) == expected.shape[:2]
    assert np.abs(out.frames[0].astype(int) - expected).mean() < LOSSY_MEAN_RESAMPLED
    assert any("rotated" in n for n in notes)


def test_full_range_carried_over(tmp_path):
    src = write_clip(tmp_path / "full.mkv", color_range=2, audio=False, frames=3)
    assert probe(src).color_range == 2
    transcode(src, tmp_path / "out.mkv", Recorder(), quiet())
    out = probe(tmp_path / "out.mkv")
    assert out.color_range == 2
    assert np.abs(out.frames[1].astype(int) - picture(1, 96, 64)).mean() < LOSSY_MEAN


# ---------------------------------------------------------------------------- encoders


def test_webm_vp9_with_opus_reencode_notice(cfr, tmp_path):
    notes: list[str] = []
    stats = transcode(cfr, tmp_path / "out.webm", invert, quiet(notes=notes))
    out = probe(tmp_path / "out.webm")
    assert out.codec == "vp9" and out.pix_fmt == "yuv420p" and out.audio_codec == "opus"
    assert stats.audio == "libopus"
    assert notes == [".webm files cannot hold aac audio: re-encoding it to libopus"]
    assert out.times == pytest.approx(probe(cfr).times, abs=1e-3)
    assert out.audio_times[-1] == pytest.approx(1.0, abs=0.05)


def test_mkv_copies_audio(cfr, tmp_path):
    transcode(cfr, tmp_path / "out.mkv", invert, quiet())
    out = probe(tmp_path / "out.mkv")
    assert out.codec == "h264" and out.audio_packets == probe(cfr).audio_packets


def test_audio_aac_and_none(cfr, tmp_path):
    stats = transcode(cfr, tmp_path / "aac.mov", invert, quiet(audio="aac"))
    out = probe(tmp_path / "aac.mov")
    assert stats.audio == "aac" and out.audio_codec == "aac"
    assert out.audio_packets != probe(cfr).audio_packets  # re-encoded
    transcode(cfr, tmp_path / "none.mp4", invert, quiet(audio="none"))
    assert probe(tmp_path / "none.mp4").audio_codec is None


def test_encoder_settings_reach_the_encoder(cfr, tmp_path):
    opts = quiet(codec="libx265", crf=30, preset="ultrafast", pix_fmt="yuv444p")
    opts.encoder_opts = {"x265-params": "log-level=error"}
    transcode(cfr, tmp_path / "out.mkv", invert, opts)
    out = probe(tmp_path / "out.mkv")
    assert (out.codec, out.pix_fmt) == ("hevc", "yuv444p")
    dst = tmp_path / "small.mp4"
    transcode(cfr, dst, invert, quiet(crf=51, preset="ultrafast", encoder_opts={"g": "5"}))
    assert dst.stat().st_size < (tmp_path / "out.mkv").stat().st_size * 4


def test_faststart_moov_before_mdat(cfr, tmp_path):
    transcode(cfr, tmp_path / "out.mp4", invert, quiet())
    data = (tmp_path / "out.mp4").read_bytes()
    assert 0 < data.index(b"moov") < data.index(b"mdat")


@pytest.mark.parametrize(
    "dst, kw, match",
    [
        ("out.avi", {}, "unknown output extension"),
        ("out.mp4", {"codec": "nope264"}, "unknown video encoder"),
        ("out.mp4", {"codec": "aac"}, "not a video encoder"),
        ("out.webm", {"codec": "libx264"}, "cannot hold h264"),
        ("out.mp4", {"pix_fmt": "yuv999p"}, "unknown pixel format"),
        ("out.mp4", {"preset": "fast", "codec": "libvpx-vp9"}, "--preset"),
        ("out.mp4", {"preset": "superfast2"}, "no preset 'superfast2'"),
        ("out.mp4", {"crf": 99}, "--crf"),
        ("out.mp4", {"encoder_opts": {"nosuchkey": "1"}}, "no option 'nosuchkey'"),
        ("out.mp4", {"encoder_opts": {"crf": "banana"}}, "crf=banana"),
        ("out.webm", {"audio": "aac"}, "cannot hold AAC"),
        ("out.mp4", {"audio": "mp3"}, "audio must be"),
        ("out.mp4", {"start": 2.0, "end": 1.0}, "must be after start"),
    ],
)
def test_bad_options_refused_before_writing(cfr, tmp_path, dst, kw, match):
    with pytest.raises(UsageError, match=match):
        transcode(cfr, tmp_path / dst, invert, quiet(**kw))
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------- range


def test_start_end_range(cfr, tmp_path):
    rec = Recorder()
    dst = tmp_path / "cut.mp4"
    stats = transcode(cfr, dst, rec, quiet(start=0.3, end=0.7))
    # frames with 0.3 <= t < 0.7: 8..17; t on the input clock, output from 0
    assert rec.times == pytest.approx([i / 25 for i in range(8, 18)])
    out = probe(dst)
    assert stats.frames == len(out.pts) == 10
    assert out.times == pytest.approx([i / 25 for i in range(10)])
    assert out.audio_times[0] == pytest.approx(0, abs=0.025)
    assert out.audio_times[-1] == pytest.approx(0.4, abs=0.05)
    src_audio = probe(cfr).audio_packets
    first = src_audio.index(out.audio_packets[0])  # copied, bit-exact, contiguous
    assert out.audio_packets == src_audio[first : first + len(out.audio_packets)]


def test_iter_frames(cfr):
    got = list(iter_frames(cfr, invert, VideoOptions(start=0.5)))
    assert [t for t, _ in got] == pytest.approx([i / 25 for i in range(13, 25)])
    assert got[0][1].shape == (64, 96, 4)
    plain = list(iter_frames(cfr, options=VideoOptions(end=0.1)))
    assert len(plain) == 3
    assert np.abs(got[0][1][..., :3].astype(int) - (255 - picture(13, 96, 64))).mean() < LOSSY_MEAN


def test_render_sheet(tmp_path):
    seen: list[float] = []

    def render_at(t):
        seen.append(t)
        img = np.zeros((48, 64, 4), np.uint8)
        img[..., 0] = int(t * 100)
        return img

    stats = render_sheet(tmp_path / "blank.webm", render_at, 0.5, 24, quiet())
    out = probe(tmp_path / "blank.webm")
    assert seen == [i / 24 for i in range(12)] and stats.frames == 12
    assert stats.duration == pytest.approx(0.5) and stats.size == (64, 48)
    assert out.times == pytest.approx([i / 24 for i in range(12)], abs=1e-3)
    assert out.audio_codec is None


# ---------------------------------------------------------------------------- errors


def test_missing_empty_and_text_inputs(tmp_path):
    (tmp_path / "empty.mp4").write_bytes(b"")
    (tmp_path / "text.mp4").write_text("not a video at all\n" * 20)
    (tmp_path / "folder.mp4").mkdir()
    cases = [
        ("missing.mp4", "no such", 1),  # media faults are exit 1, stills alike
        ("folder.mp4", "is a folder", 1),
        ("empty.mp4", "empty", 1),
        ("text.mp4", "not a", 1),
    ]
    for name, what, code in cases:
        with pytest.raises((MediaError, UsageError), match=what) as err:
            transcode(tmp_path / name, tmp_path / "out.mp4", invert, quiet())
        assert name in str(err.value) and "\n" not in str(err.value)
        assert err.value.exit_code == code
    assert not (tmp_path / "out.mp4").exists() and leftovers(tmp_path) == []


def test_output_equal_to_input_refused(cfr):
    with pytest.raises(UsageError, match="same file"):
        transcode(cfr, cfr, invert, quiet(overwrite=True))


def test_existing_output_kept_without_overwrite(cfr, tmp_path):
    dst = tmp_path / "out.mp4"
    dst.write_bytes(b"precious")
    with pytest.raises(OutputExistsError):
        transcode(cfr, dst, invert, quiet())
    assert dst.read_bytes() == b"precious"
    transcode(cfr, dst, invert, quiet(overwrite=True))
    assert len(probe(dst).pts) == 25


def test_transform_error_propagates_and_leaves_nothing(cfr, tmp_path):
    def boom(rgba, t):
        if t > 0.3:
            raise RuntimeError("kernel exploded")
        return rgba

    with pytest.raises(RuntimeError, match="kernel exploded"):
        transcode(cfr, tmp_path / "out.mp4", boom, quiet())
    assert list(tmp_path.iterdir()) == []


def test_bad_transform_result(cfr, tmp_path):
    with pytest.raises(TypeError, match="uint8"):
        transcode(cfr, tmp_path / "out.mp4", lambda a, t: a.astype(np.float32), quiet())
    assert list(tmp_path.iterdir()) == []


def test_encoder_failure_is_media_error(tmp_path):
    """What the settings check cannot see: MPEG-4 part 2 takes no time base
    finer than 1/65535, and the output keeps the input's 1/90000."""
    tb = Fraction(1, 90000)
    src = write_clip(tmp_path / "in.mp4", size=(64, 48), frames=3, audio=False, time_base=tb)
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(MediaError, match="mpeg4 encoding failed"):
        transcode(src, out / "out.mp4", invert, quiet(codec="mpeg4"))
    assert list(out.iterdir()) == []


def test_corrupt_packet_skipped_with_count(tmp_path):
    src = write_clip(tmp_path / "bad.mkv", codec="mpeg4", corrupt_at=12)
    notes: list[str] = []
    stats = transcode(src, tmp_path / "out.mp4", invert, quiet(notes=notes))
    assert stats.corrupt_packets == 1
    assert notes == [f"{src}: skipped 1 corrupt packet(s)"]
    out = probe(tmp_path / "out.mp4")
    assert len(out.pts) == stats.frames == 24


# ---------------------------------------------------------------------------- threads


def test_queues_are_bounded():
    assert 1 <= QUEUE_FRAMES <= 8
    pipe = Stages()
    q: queue.Queue = queue.Queue(QUEUE_FRAMES)
    for i in range(QUEUE_FRAMES):
        pipe.put(q, i)
    assert q.full()
    pipe.stop.set()
    with pytest.raises(Stopped):
        pipe.put(q, "one too many")  # does not block forever once stopped


INTERRUPT_SCRIPT = """
import sys, time
from marblevideo.jobs.pipeline import transcode
from marblevideo.media.video import VideoOptions
def slow(rgba, t):
    print("frame", flush=True)
    time.sleep(0.2)
    return rgba
transcode(sys.argv[1], sys.argv[2], slow, VideoOptions(progress="off"))
"""


def test_sigint_stops_promptly_and_leaves_nothing(tmp_path):
    src = write_clip(tmp_path / "long.mp4", frames=100)
    work = tmp_path / "work"
    work.mkdir()
    env = subprocess_env()
    proc = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(INTERRUPT_SCRIPT), str(src), str(work / "o.mp4")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=env,
        text=True,
    )
    for _ in range(3):  # a few frames are through: the temp output is being written
        assert proc.stdout.readline() == "frame\n"
    assert leftovers(work)
    began = time.monotonic()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=10)
    assert time.monotonic() - began < 5
    assert proc.returncode != 0 and "KeyboardInterrupt" in err
    assert list(work.iterdir()) == []


# ---------------------------------------------------------------------------- progress


def test_progress_json_lines(capsys):
    import json

    with Progress(3, mode="json", interval=0.0) as bar:
        for _ in range(3):
            bar.update()
    lines = [json.loads(x) for x in capsys.readouterr().err.splitlines()]
    assert lines[-1]["frame"] == 3 and lines[-1]["total"] == 3
    assert set(lines[0]) == {"frame", "total", "fps", "time", "eta"}
    # other units are named as such (segments of --cluster, items of a batch)
    with Progress(2, mode="json", unit="segment", interval=0.0) as bar:
        bar.update()
    lines = [json.loads(x) for x in capsys.readouterr().err.splitlines()]
    assert set(lines[0]) == {"segment", "total", "per_second", "time", "eta"}
    assert (lines[0]["segment"], lines[-1]["segment"], lines[-1]["total"]) == (1, 1, 2)
