"""Streaming a live session to a real RTMP server on loopback (nginx-rtmp, run
by the tests): the server receives H.264 + AAC of the right size and rate that
an independent reader decodes into the marbled picture, beside a recording; the
session outlives the server going away and resumes when it returns."""

from __future__ import annotations

import json
import subprocess
import sys
import time

import av
import numpy as np
import pytest
from clips import picture, probe, write_clip
from helpers import one_line, subprocess_env
from live_helpers import LiveProcess
from rtmp_server import RtmpServer, missing

pytestmark = pytest.mark.tier("integration")

# a still design (no time in it): a frame streamed is a file render's frame
STILL = {
    "marblevideo": 1,
    "ops": [{"type": "vortex", "center": [80, 48], "alpha": 160, "lambda": 40}],
}
SIZE = (160, 96)


def marblevideo(*args, cwd, timeout=300) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "marblevideo", *map(str, args)]
    return subprocess.run(
        cmd, cwd=cwd, env=subprocess_env(), capture_output=True, text=True, timeout=timeout
    )


@pytest.fixture
def server(tmp_path):
    if why := missing():
        pytest.skip(why)
    rtmp = RtmpServer(tmp_path / "nginx")
    rtmp.start()
    yield rtmp
    rtmp.stop()


def ffprobe_streams(path) -> dict:
    """FFmpeg's own reader's view of a file's streams, by type."""
    out = subprocess.run(
        ["ffprobe", "-v", "error", "-show_streams", "-of", "json", str(path)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return {s["codec_type"]: s for s in json.loads(out)["streams"]}


def nearest(frame: np.ndarray, frames: list[np.ndarray]) -> float:
    """The mean absolute difference from ``frame`` to the closest of ``frames``."""
    return min(float(np.abs(frame.astype(int) - f.astype(int)).mean()) for f in frames)


def test_a_stream_and_a_recording_at_once_carry_the_marbled_picture(tmp_path, server):
    clip = write_clip(tmp_path / "clip.mp4", size=SIZE, frames=45, fps=15, audio=False)
    (tmp_path / "still.json").write_text(json.dumps(STILL))
    url = server.url("key1")
    live = marblevideo(
        "live", clip, "--ops", "still.json", "-o", url, "-o", "take.mp4", cwd=tmp_path
    )
    assert live.returncode == 0, live.stderr
    assert "key1" not in live.stderr, "the stream key is shown"
    ref = marblevideo(clip, "--ops", "still.json", "-o", "ref.mp4", cwd=tmp_path)
    assert ref.returncode == 0, ref.stderr

    [received] = server.recordings()
    streams = ffprobe_streams(received)
    assert streams["video"]["codec_name"] == "h264"
    assert (streams["video"]["width"], streams["video"]["height"]) == SIZE
    assert streams["audio"]["codec_name"] == "aac"
    assert int(streams["audio"]["sample_rate"]) == 48000
    got, recorded = probe(received), probe(tmp_path / "take.mp4")
    # the frames shown (a loaded machine drops some) reach both, at their capture times
    assert len(recorded.frames) >= 15
    assert len(got.frames) >= 0.8 * len(recorded.frames), (len(got.frames), len(recorded.frames))
    shown_at = np.round(np.subtract(recorded.times, recorded.times[0]) * 1000)
    assert set(np.round(np.subtract(got.times, got.times[0]) * 1000)) <= set(shown_at)
    assert np.median(np.diff(got.times)) == pytest.approx(1 / 15, abs=0.015)
    assert got.audio_packets and got.audio_times[-1] >= got.times[-1] - 0.1
    marbled = probe(tmp_path / "ref.mp4").frames
    plain = [picture(i, *SIZE) for i in range(45)]
    for frame in got.frames:
        to_render, to_source = nearest(frame, marbled), nearest(frame, plain)
        assert to_render < 4, to_render
        assert to_render * 4 < to_source, (to_render, to_source)


def test_the_session_goes_on_while_the_server_is_away_and_the_stream_resumes(tmp_path, server):
    (tmp_path / "still.json").write_text(json.dumps(STILL))
    url = server.url("key2")
    args = ["test", "--ops", "still.json", "--size", "160x96", "--fps", "15", "--duration", "18"]
    live = LiveProcess(*args, "-o", url, "-o", "take.mp4", "--preview", "--port", "0", cwd=tmp_path)
    try:
        first = live.wait_stats(lambda s: s["streams"][0]["sent"] >= 15, timeout=60)
        assert first["streams"][0]["connected"]
        server.stop()
        away = live.wait_stats(lambda s: not s["streams"][0]["connected"], timeout=10)
        frames = away["frames"]
        # the session goes on marbling without the server (within 10 s; not a fixed wait)
        live.wait_stats(lambda s: s["frames"] > frames, timeout=10)
        server.start()
        back_at = time.monotonic()
        back = live.wait_stats(lambda s: s["streams"][0]["reconnects"] == 1, timeout=10)
        assert time.monotonic() - back_at < 5
        assert back["streams"][0]["lost"] > 0
        sent = back["streams"][0]["sent"]
        live.wait_stats(lambda s: s["streams"][0]["sent"] >= sent + 10, timeout=20)
        rc = live.proc.wait(60)
    finally:
        live.stop()
    err = live.stderr()
    assert rc == 0, err
    assert err.count("the server is away") == 1, err
    assert "resumed after" in err and "lost while the server was away" in err, err
    before, after = server.recordings()
    assert len(probe(after).frames) >= 10
    recorded = probe(tmp_path / "take.mp4")
    assert recorded.times[-1] - recorded.times[0] > 15, "the recording misses part of the session"
    assert max(np.diff(recorded.times)) < 0.5, "the recording has a hole"


@pytest.mark.parametrize(
    ("outputs", "fault"),
    [
        (["rtmp://127.0.0.1/live"], "expected rtmp://HOST[:PORT]/APP/KEY"),
        (["http://127.0.0.1/live/key"], "cannot stream to http://"),
        (["a.mp4", "b.mp4"], "one recording at a time"),
        (["rtmp://127.0.0.1/a/k", "rtmp://127.0.0.1/a/k"], "is given twice"),
    ],
)
def test_a_bad_stream_output_is_one_line_and_exit_2(tmp_path, outputs, fault):
    (tmp_path / "still.json").write_text(json.dumps(STILL))
    args = [arg for name in outputs for arg in ("-o", name)]
    proc = marblevideo(
        "live", "test", "--ops", "still.json", *args, "--duration", "1", cwd=tmp_path
    )
    assert proc.returncode == 2
    assert fault in one_line(proc)
    assert not list(tmp_path.glob("*.mp4"))


def keyframe_times(path) -> list[float]:
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        return [
            float(p.pts * p.time_base)
            for p in container.demux(stream)
            if p.is_keyframe and p.pts is not None
        ]


def test_a_file_render_plays_at_its_own_pace_with_a_keyframe_every_2_s(tmp_path, server):
    clip = write_clip(tmp_path / "clip.mp4", size=SIZE, frames=60, fps=15, audio=False)
    (tmp_path / "still.json").write_text(json.dumps(STILL))
    start = time.monotonic()
    proc = marblevideo(
        clip, "--ops", "still.json", "-o", server.url("k5"), "--realtime", cwd=tmp_path
    )
    assert proc.returncode == 0, proc.stderr
    assert time.monotonic() - start > 4, "not played at the clip's pace"
    [received] = server.recordings()
    got = probe(received)
    assert got.times[-1] - got.times[0] == pytest.approx(59 / 15, abs=0.5)
    keys = keyframe_times(received)
    assert len(keys) == 2 and keys[1] - keys[0] == pytest.approx(2.0, abs=0.15), keys
