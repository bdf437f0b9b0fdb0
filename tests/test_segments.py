"""A video in segments without an engine: the plan at keyframes, each segment
through the normal pipeline, the join by packet copy; against single renders
of a clip with B-frames at a variable frame rate. The Ray executor: test_cluster.py."""

from __future__ import annotations

import subprocess
import sys

import av
import numpy as np
import pytest
from clips import probe, write_clip, write_vfr_clip
from helpers import files, one_line, subprocess_env
from recipes import BRIEF

from marblevideo import api
from marblevideo.jobs.segments import plan_segments
from marblevideo.scale.segmented import render_split

pytestmark = pytest.mark.tier("integration")


@pytest.fixture(scope="module")
def vfr(tmp_path_factory):
    return write_vfr_clip(tmp_path_factory.mktemp("vfr") / "in.mp4")


def keyframes(path) -> list[int]:
    with av.open(str(path)) as container:
        video = container.streams.video[0]
        return [p.pts for p in container.demux(video) if p.size and p.is_keyframe]


def test_segments_start_at_keyframes_and_own_every_frame_once(vfr):
    parts = plan_segments(vfr, 3)
    assert [(s.index, s.count) for s in parts] == [(0, 3), (1, 3), (2, 3)]
    assert parts[0].start is None and parts[-1].end is None
    assert all(a.end == b.start for a, b in zip(parts, parts[1:], strict=False))
    with av.open(str(vfr)) as container:
        tb = container.streams.video[0].time_base
        shown = sorted(p.pts for p in container.demux(container.streams.video[0]) if p.size)
    starts = {round(s.start / tb) for s in parts[1:]}
    assert starts <= set(keyframes(vfr))
    for part in parts[1:]:  # the frame shown before a segment: the one before its start
        assert part.before == float(max(p for p in shown if p < part.origin) * tb)
    assert len(plan_segments(vfr)) == 1  # 2.6 s: one segment of about 45 s
    assert len(plan_segments(vfr, 50)) == len(keyframes(vfr))  # no more than keyframes


def test_in_segments_equals_a_single_render_at_crf_0(vfr, tmp_path):
    single = api.render_video(vfr, BRIEF, tmp_path / "single.mp4", crf=0, quiet=True)
    split = render_split(vfr, BRIEF, tmp_path / "split.mp4", cluster="serial", segments=3,
                         crf=0, quiet=True)  # fmt: skip
    assert split.frames == single.frames == 48
    assert files(tmp_path) == ["single.mp4", "split.mp4"]  # the segments' folder is gone
    a, b = probe(tmp_path / "single.mp4"), probe(tmp_path / "split.mp4")
    assert b.pts == a.pts and b.time_base == a.time_base
    assert b.audio_packets == a.audio_packets and b.audio_times == a.audio_times
    assert len(b.frames) == len(a.frames)
    for i, (x, y) in enumerate(zip(a.frames, b.frames, strict=True)):
        assert np.array_equal(x, y), i


@pytest.mark.parametrize("ext", [".mp4", ".mkv"])
def test_lossy_segments_keep_every_timestamp(vfr, tmp_path, ext):
    """x264's B-frames at the joins: decode times are moved up where a segment's
    first fall before the last of the one before; presentation times never."""
    api.render_video(vfr, "swirl", tmp_path / f"single{ext}", quiet=True)
    render_split(vfr, "swirl", tmp_path / f"split{ext}", cluster="serial", segments=4, quiet=True)
    a, b = probe(tmp_path / f"single{ext}"), probe(tmp_path / f"split{ext}")
    assert b.pts == a.pts and b.audio_packets == a.audio_packets
    with av.open(str(tmp_path / f"split{ext}")) as container:
        video = container.streams.video[0]
        stamps = [(p.pts, p.dts) for p in container.demux(video) if p.size]
    assert any(pts != dts for pts, dts in stamps)  # B-frames, reordered
    if ext == ".mp4":  # Matroska keeps no decode times
        dts = [d for _, d in stamps]
        assert all(d < e for d, e in zip(dts, dts[1:], strict=False))
        assert all(d <= p for p, d in stamps)


def test_the_output_takes_the_sources_audio_as_a_single_render(tmp_path):
    """WebM holds no AAC: the audio is re-encoded to Opus once, in the join."""
    src = write_clip(tmp_path / "in.mp4", size=(64, 48), frames=30, encoder={"g": "10"})
    stats = render_split(src, "swirl", tmp_path / "out.webm", cluster="serial", segments=3,
                         quiet=True)  # fmt: skip
    api.render_video(src, "swirl", tmp_path / "single.webm", quiet=True)
    out, single = probe(tmp_path / "out.webm"), probe(tmp_path / "single.webm")
    assert stats.audio == "libopus" and out.audio_codec == "opus" and out.codec == "vp9"
    assert len(out.frames) == 30 and out.pts == single.pts
    assert len(out.audio_packets) == len(single.audio_packets)


@pytest.mark.parametrize(
    "args, fault",
    [
        (["in.mp4", "-o", "o.mp4", "--segments", "3"], "--segments: goes with --cluster"),
        (["in.mp4", "-o", "o.mp4", "--jobs", "2"], "--jobs: goes with --cluster"),
        (["in.mp4", "-o", "o.png", "--cluster", "ray"], "renders a video file to a video"),
        (["-o", "o.mp4", "--cluster", "ray"], "not a blank sheet"),
        (["in.mp4", "-o", "o.mp4", "--cluster", "ray", "--start", "1"], "--start: not with"),
        (["in.mp4", "-o", "o.mp4", "--cluster", "ray", "--fps", "10"], "--fps: not with"),
        (["in.mp4", "-o", "o.gif", "--cluster", "ray"], "not written in one piece"),
        (
            ["in.mp4", "-o", "o.mov", "--cluster", "ray", "--codec", "qtrle", "--pix-fmt", "rgb24"],
            "MP4",
        ),
        (["in.mp4", "-o", "in.mp4", "--cluster", "ray", "-y"], "same file as the input"),
    ],
)
def test_usage_errors_before_any_work(cli, tmp_path, args, fault):
    write_clip(tmp_path / "in.mp4", size=(32, 32), frames=3, audio=False)
    proc = cli(*args, "--ops", "swirl")
    assert proc.returncode == 2, proc.stderr
    assert fault in one_line(proc)
    assert files(tmp_path) == ["in.mp4"]


def test_without_ray_the_cluster_asks_for_the_extra(tmp_path):
    """As where Ray is not installed: ``import ray`` fails in the command's process."""
    write_clip(tmp_path / "in.mp4", size=(32, 32), frames=3, audio=False)
    (tmp_path / "in").mkdir()
    for args in (["in.mp4", "-o", "o.mp4"], ["batch", "in.mp4", "-o", "in/{stem}.png"]):
        args += ["--ops", "swirl", "--cluster", "ray"]
        code = "import sys; sys.modules['ray'] = None; from marblevideo.cli import main; "
        proc = subprocess.run(
            [sys.executable, "-c", code + f"sys.exit(main({args!r}))"],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            env=subprocess_env(),
            timeout=120,
        )
        assert proc.returncode == 2, proc.stderr
        assert "pip install 'marblevideo[ray]'" in one_line(proc)
    assert files(tmp_path) == ["in", "in.mp4"]


def test_the_core_never_imports_ray():
    code = (
        "import sys, marblevideo.scale.segmented, marblevideo.scale.batch, marblevideo.cli.render; "
        "print('ray' in sys.modules)"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=subprocess_env(), timeout=60)  # fmt: skip
    assert proc.stdout.strip() == "False", proc.stderr
