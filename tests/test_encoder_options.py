"""Encoder options tried before any work, and the encoder libraries kept quiet:
real PyAV encoders, the real command line in a subprocess.

A bad --codec/--crf/--preset/--pix-fmt/--encoder-opt is exit status 2 with one
stderr line naming the flag, before the input is opened or OpenCL starts, with
nothing written. x265, SVT-AV1 and FFmpeg print nothing of their own unless
--verbose; -q prints nothing at all; a video render ends with a summary line.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import av
import pytest
from clips import write_clip
from helpers import files, one_line

from marblevideo.errors import UsageError
from marblevideo.media.encode import plan_output
from marblevideo.media.video import VideoOptions

pytestmark = pytest.mark.tier("integration")

RECIPE = {
    "canvas": [64, 48],
    "antialias": "none",
    "ops": [
        {"type": "drop", "center": [32, 24], "radius": 10, "color": "#cc2200"},
        {"type": "vortex", "center": [32, 24], "alpha": 90, "lambda": 20},
    ],
}
SUMMARY = re.compile(
    r"marblevideo: wrote (\S+): (\d+) frames, (\d+\.\d\d) s, (\d+)x(\d+), \d+\.\d fps"
)


def has_encoder(name: str) -> bool:
    try:
        av.Codec(name, "w")
    except (ValueError, av.error.FFmpegError):
        return False
    return True


def needs(codec: str):
    return pytest.mark.skipif(not has_encoder(codec), reason=f"this FFmpeg has no {codec}")


@pytest.fixture(autouse=True)
def svt_log_kept():
    """plan_output sets SVT_LOG for libsvtav1 in this process: put it back, so the
    command lines below start from the environment they were given."""
    before = os.environ.get("SVT_LOG")
    yield
    if before is None:
        os.environ.pop("SVT_LOG", None)
    else:
        os.environ["SVT_LOG"] = before


@pytest.fixture
def work(tmp_path) -> Path:
    """A folder with a tiny clip (64x48, 5 frames at 25 fps, AAC audio) and a recipe."""
    write_clip(tmp_path / "in.mp4", size=(64, 48), frames=5, fps=25)
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    return tmp_path


# ---------------------------------------------------------------------------- plan_output

BAD = [
    ("o.mp4", {"preset": "superfast2"}, ["--preset:", "'superfast2'", "ultrafast, superfast"]),
    ("o.mp4", {"crf": 99}, ["--crf:", "libx264", "0..51", "99"]),
    ("o.mp4", {"crf": -1}, ["--crf:", "0..51", "-1"]),
    ("o.mp4", {"encoder_opts": {"nosuchkey": "1"}}, ["--encoder-opt:", "'nosuchkey'"]),
    ("o.mp4", {"encoder_opts": {"rc_lookahead": "5"}}, ["did you mean 'rc-lookahead'?"]),
    ("o.mp4", {"encoder_opts": {"skip_frame": "nokey"}}, ["'skip_frame'", "encoding video"]),
    ("o.mp4", {"encoder_opts": {"time_base": "1/25"}}, ["'time_base'"]),
    ("o.mp4", {"encoder_opts": {"tune": "nosuch"}}, ["--encoder-opt:", "tune", "zerolatency"]),
    ("o.mp4", {"encoder_opts": {"g": "abc"}}, ["--encoder-opt:", "g=abc", "Unable to parse"]),
    ("o.mp4", {"encoder_opts": {"crf": "banana"}}, ["--encoder-opt:", "crf=banana"]),
    ("o.mp4", {"encoder_opts": {"x264-params": "nosuch=1"}}, ["x264-params=nosuch=1"]),
    ("o.mp4", {"pix_fmt": "yuv444p", "encoder_opts": {"profile": "baseline"}}, ["profile"]),
    ("o.mp4", {"codec": "mpeg4", "crf": 20}, ["--crf:", "mpeg4", "'crf'"]),
    ("o.webm", {"crf": 64}, ["--crf:", "libvpx-vp9", "0..63", "64"]),
    ("o.webm", {"encoder_opts": {"deadline": "fast"}}, ["'fast'", "best, good, realtime"]),
    ("o.webm", {"encoder_opts": {"cpu-used": "9"}}, ["cpu-used -8..8, got 9"]),
    ("o.webm", {"preset": "fast"}, ["--preset:", "libvpx-vp9 has no presets"]),
]
BAD_X265 = [
    ("o.mkv", {"codec": "libx265", "crf": 60}, ["--crf:", "libx265", "0..51", "60"]),
    ("o.mp4", {"codec": "libx265", "preset": "superfast2"}, ["--preset:", "placebo"]),
    ("o.mkv", {"codec": "libx265", "encoder_opts": {"x265-params": "nosuch=1"}}, ["nosuch"]),
    ("o.mkv", {"codec": "libx265", "encoder_opts": {"x265-params": "keyint=x"}}, ["keyint"]),
]
BAD_SVT = [
    ("o.mkv", {"codec": "libsvtav1", "crf": 99}, ["--crf:", "libsvtav1", "0..63", "99"]),
    ("o.mkv", {"codec": "libsvtav1", "preset": "14"}, ["--preset:", "-2..13", "14"]),
    ("o.mkv", {"codec": "libsvtav1", "encoder_opts": {"svtav1-params": "nosuch=1"}}, ["nosuch"]),
]


@pytest.mark.parametrize(
    "dst, kw, needles",
    BAD
    + [pytest.param(*case, marks=needs("libx265")) for case in BAD_X265]
    + [pytest.param(*case, marks=needs("libsvtav1")) for case in BAD_SVT],
)
def test_bad_encoder_settings_refused_in_one_line(tmp_path, capfd, dst, kw, needles):
    with pytest.raises(UsageError) as err:
        plan_output(tmp_path / dst, VideoOptions(**kw))
    message = str(err.value)
    assert "\n" not in message
    for needle in needles:
        assert needle in message, message
    # the throw-away encoder printed nothing (x264 and x265 write straight to fd 2)
    assert capfd.readouterr().err == ""
    assert files(tmp_path) == []


GOOD = [
    ("o.mp4", {"preset": "veryfast", "crf": 0, "encoder_opts": {"tune": "film,zerolatency"}}),
    ("o.mp4", {"pix_fmt": "yuv444p", "encoder_opts": {"profile": "high444", "g": "5"}}),
    ("o.mp4", {"encoder_opts": {"x264-params": "keyint=5:bframes=0", "threads": "auto"}}),
    ("o.webm", {"crf": 63, "encoder_opts": {"deadline": "realtime", "cpu-used": "8"}}),
    ("o.mp4", {"codec": "mpeg4", "encoder_opts": {"flags": "+qscale", "global_quality": "90"}}),
]


@pytest.mark.parametrize(
    "dst, kw",
    GOOD
    + [
        pytest.param("o.mkv", {"codec": "libx265", "crf": 51}, marks=needs("libx265")),
        pytest.param("o.mkv", {"codec": "libsvtav1", "preset": "12"}, marks=needs("libsvtav1")),
    ],
)
def test_good_encoder_settings_pass(tmp_path, capfd, dst, kw):
    plan = plan_output(tmp_path / dst, VideoOptions(**kw))
    for key, value in kw.get("encoder_opts", {}).items():
        assert plan.codec_options[key] == value
    assert capfd.readouterr().err == "" and files(tmp_path) == []


@needs("libx265")
def test_x265_log_level_merged_with_the_users_params(tmp_path):
    def params(verbose=False, given=None):
        opts = {"x265-params": given} if given is not None else {}
        kw = dict(codec="libx265", encoder_opts=opts, verbose=verbose)
        return plan_output(tmp_path / "o.mkv", VideoOptions(**kw)).codec_options.get("x265-params")

    assert params() == "log-level=none"
    assert params(given="keyint=5:bframes=2") == "log-level=none:keyint=5:bframes=2"
    assert params(given="keyint=5:log-level=info") == "keyint=5:log-level=info"  # theirs wins
    assert params(given="log=warning") == "log=warning"
    assert params(verbose=True) is None
    assert params(verbose=True, given="keyint=5") == "keyint=5"


# ---------------------------------------------------------------------------- command line

CLI_BAD = [
    (["--preset", "superfast2"], "--preset: libx264 has no preset 'superfast2' (ultrafast,"),
    (["--crf", "99"], "--crf: libx264 takes crf 0..51, got 99"),
    (["--crf", "-4"], "--crf: libx264 takes crf 0..51, got -4"),
    (["--pix-fmt", "yuv999p"], "unknown pixel format 'yuv999p'"),
    (["--codec", "nope264"], "unknown video encoder 'nope264'"),
    (["--encoder-opt", "nosuchkey=1"], "--encoder-opt: libx264 has no option 'nosuchkey'"),
    (["--encoder-opt", "presett=fast"], "(did you mean 'preset'?)"),
]


@pytest.mark.parametrize("args, expected", CLI_BAD)
def test_cli_refuses_bad_encoder_settings_before_any_work(cli, work, args, expected):
    proc = cli("in.mp4", "--ops", "r.json", "-o", "out.mp4", *args)
    assert proc.returncode == 2
    line = one_line(proc)
    assert expected in line, line
    assert files(work) == ["in.mp4", "r.json"]  # no output, no temporary file


def test_cli_checks_the_encoder_before_the_input_and_the_device(cli, work):
    """A missing input (exit 1) and an unknown device (another line) would be
    reported first if either were looked at before the encoder settings."""
    proc = cli("missing.mp4", "--ops", "r.json", "-o", "o.mp4", "--device", "99:99", "--crf", "70")
    assert proc.returncode == 2
    assert one_line(proc) == "marblevideo: --crf: libx264 takes crf 0..51, got 70"
    assert files(work) == ["in.mp4", "r.json"]


def test_blank_sheet_and_live_recording_check_the_encoder(cli, work):
    proc = cli("--ops", "r.json", "-o", "o.webm", "--encoder-opt", "deadline=fast")
    assert proc.returncode == 2 and "deadline 'fast'" in one_line(proc)
    proc = cli("live", "test", "--ops", "r.json", "-o", "rec.mp4", "--preset", "superfast2")
    assert proc.returncode == 2 and "--preset: libx264 has no preset" in one_line(proc)
    proc = cli("live", "test", "--ops", "r.json", "-o", "rec.mp4", "--encoder-opt", "bad=1")
    assert proc.returncode == 2 and "'bad'" in one_line(proc)
    assert files(work) == ["in.mp4", "r.json"]


QUIET_CASES = [
    pytest.param("libx265", "out.mp4", "hevc", marks=needs("libx265")),
    pytest.param("libx265", "out.mkv", "hevc", marks=needs("libx265")),
    pytest.param("libsvtav1", "out.mkv", "av1", marks=needs("libsvtav1")),
    pytest.param("libvpx-vp9", "out.webm", "vp9", marks=needs("libvpx-vp9")),
]


@pytest.mark.parametrize("codec, out, decoded", QUIET_CASES)
def test_encoder_libraries_print_nothing(cli, work, codec, out, decoded):
    """-q: stderr stays empty (the .webm's Opus re-encode note included); by default
    only marblevideo's own lines, ending with the summary."""
    proc = cli("in.mp4", "--ops", "r.json", "-o", out, "--codec", codec, "-q")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    with av.open(str(work / out)) as got:
        stream = got.streams.video[0]
        assert stream.codec_context.codec.canonical_name == decoded
        assert sum(1 for _ in got.decode(stream)) == 5
    proc = cli("in.mp4", "--ops", "r.json", "-o", out, "--codec", codec, "-y")
    assert proc.returncode == 0, proc.stderr
    assert "x265 [" not in proc.stderr and "Svt[" not in proc.stderr, proc.stderr
    lines = proc.stderr.splitlines()
    assert lines and all(line.startswith("marblevideo: ") for line in lines), proc.stderr
    assert SUMMARY.fullmatch(lines[-1]), lines[-1]


@pytest.mark.parametrize(
    "codec, out, marker",
    [
        pytest.param("libx265", "out.mkv", "x265 [info]", marks=needs("libx265")),
        pytest.param("libsvtav1", "out.mkv", "Svt[info]", marks=needs("libsvtav1")),
    ],
)
def test_verbose_lets_the_library_lines_through(cli, work, codec, out, marker):
    if codec == "libsvtav1" and "SVT_LOG" in os.environ:
        pytest.skip("SVT_LOG is set in this environment")
    proc = cli("in.mp4", "--ops", "r.json", "-o", out, "--codec", codec, "-q", "--verbose")
    assert proc.returncode == 0, proc.stderr
    assert marker in proc.stderr


# ---------------------------------------------------------------------------- summary


def test_summary_line_for_a_video_input(cli, work):
    proc = cli("in.mp4", "--ops", "r.json", "-o", "out.mkv", "--progress", "off")
    assert proc.returncode == 0, proc.stderr
    match = SUMMARY.fullmatch(proc.stderr.splitlines()[-1])
    assert match, proc.stderr
    assert match.groups()[:5] == ("out.mkv", "5", "0.20", "64", "48")
    proc = cli("in.mp4", "--ops", "r.json", "-o", "quiet.mkv", "-q")
    assert proc.returncode == 0 and proc.stderr == ""


def test_summary_line_for_a_blank_sheet(cli, work):
    args = ("--ops", "r.json", "--duration", "0.5", "--fps", "10", "--size", "63x47")
    proc = cli(*args, "-o", "sheet.mp4")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert lines[0].startswith("marblevideo: 63x47 padded to 64x48")  # a note, then the summary
    match = SUMMARY.fullmatch(lines[-1])
    assert match and match.groups()[:5] == ("sheet.mp4", "5", "0.50", "64", "48"), proc.stderr
    proc = cli(*args, "-o", "quiet.mp4", "-q")
    assert proc.returncode == 0 and proc.stderr == ""


@needs("libsvtav1")
@pytest.mark.skipif(
    not hasattr(os, "sched_getscheduler") or os.geteuid() != 0,
    reason="SVT-AV1 makes threads real-time only when run as root (Linux)",
)
def test_svt_av1_leaves_no_thread_real_time(work):
    """SVT-AV1, run as root, makes the thread that opens it, and its own threads,
    SCHED_FIFO 99; the programs that thread starts inherit it, and busy ones then
    starve a small machine. After its options are tried and an AV1 render, this
    process and what it starts are scheduled as before."""
    import subprocess
    import sys

    from marblevideo import api
    from marblevideo.media.scheduling import realtime_threads

    policy = os.sched_getscheduler(0)
    plan_output(work / "probe.mkv", VideoOptions(codec="libsvtav1", crf=30))
    api.render_video(work / "in.mp4", work / "r.json", work / "o.mkv", codec="libsvtav1")
    with av.open(str(work / "o.mkv")) as written:
        assert written.streams.video[0].codec_context.codec.canonical_name == "av1"
    assert os.sched_getscheduler(0) == policy
    assert realtime_threads() == []
    child = subprocess.run(
        [sys.executable, "-c", "import os; print(os.sched_getscheduler(0))"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert int(child.stdout) == policy
