"""Both commands on a real local Ray cluster (127.0.0.1, two CPUs, one per
module): a clip with B-frames at a variable frame rate in 3 segments against
the single render, a worker that crashes (``os._exit``) once and one that
crashes every time, a batch of stills against single renders."""

from __future__ import annotations

import os

import cv2
import numpy as np
import pytest
from clips import probe, write_vfr_clip
from helpers import ROOT, files, one_line
from recipes import BRIEF

from marblevideo import api
from marblevideo.jobs.segments import plan_segments
from marblevideo.scale.batch import MANIFEST_NAME
from marblevideo.scale.cluster import CRASH_ENV, CRASH_MARKER_ENV, RayPool, connect
from marblevideo.scale.segmented import render_split

pytestmark = pytest.mark.tier("integration")

ray = pytest.importorskip("ray", reason="the extra: pip install 'marblevideo[ray]'")


@pytest.fixture(scope="module")
def cluster():
    """A local Ray for the module; its address, for commands run as subprocesses."""
    assert connect(ray, num_cpus=2)  # as the commands start one
    try:
        yield ray.get_runtime_context().gcs_address
    finally:
        ray.shutdown()


@pytest.fixture(scope="module")
def clip(tmp_path_factory, cluster):
    """The clip, its single render at --crf 0 (decoded), and its 3 segments."""
    folder = tmp_path_factory.mktemp("ray")
    src = write_vfr_clip(folder / "in.mp4")
    api.render_video(src, BRIEF, folder / "single.mp4", crf=0, quiet=True)
    return src, probe(folder / "single.mp4"), plan_segments(src, 3)


def same_video(path, single) -> None:
    out = probe(path)
    assert out.pts == single.pts and out.time_base == single.time_base
    assert out.audio_packets == single.audio_packets and out.audio_times == single.audio_times
    assert len(out.frames) == len(single.frames) == 48
    for i, (a, b) in enumerate(zip(out.frames, single.frames, strict=True)):
        assert np.array_equal(a, b), i


@pytest.mark.parametrize("asked", [None, 8])
def test_workers_run_this_code_with_their_share_of_the_cpus(cluster, asked):
    pool = RayPool(asked)
    try:
        where = pool.where()
    finally:
        pool.close()
    assert len(where) == 2  # one per CPU, never more (more could not all be placed)
    assert {(path, threads) for _, path, _, threads in where} == {(str(ROOT), "1")}
    pids = {pid for _, _, pid, _ in where}
    assert len(pids) == 2 and os.getpid() not in pids


def test_three_segments_on_ray_equal_the_single_render(clip, tmp_path):
    src, single, parts = clip
    stats = render_split(src, BRIEF, tmp_path / "out.mp4", segments=3, crf=0, quiet=True)
    assert stats.frames == 48 and len(parts) == 3
    same_video(tmp_path / "out.mp4", single)
    assert files(tmp_path) == ["out.mp4"]


def test_a_worker_crashing_once_changes_nothing(clip, tmp_path, monkeypatch):
    src, single, parts = clip
    monkeypatch.setenv(CRASH_ENV, str(parts[1]))
    monkeypatch.setenv(CRASH_MARKER_ENV, str(tmp_path / "crashed"))
    render_split(src, BRIEF, tmp_path / "out.mp4", segments=3, crf=0, quiet=True)
    assert (tmp_path / "crashed").exists()  # segment 2's worker died once
    same_video(tmp_path / "out.mp4", single)


def test_a_segment_that_always_fails_is_named_and_nothing_is_left(clip, cli, cluster, tmp_path):
    src, _, parts = clip
    env = {CRASH_ENV: str(parts[2]), "RAY_ADDRESS": cluster}
    proc = cli(src, "--ops", "swirl", "-o", "out.mp4", "--cluster", "ray", "--segments", 3,
               env=env)  # fmt: skip
    assert proc.returncode == 1, proc.stderr
    line = one_line(proc)
    assert f"{parts[2]} failed" in line and "died 3 times" in line
    assert files(tmp_path) == []


def test_a_batch_of_stills_on_ray_equals_single_renders(cli, cluster, tmp_path):
    (tmp_path / "in").mkdir()
    (tmp_path / "out").mkdir()
    for i in range(3):
        image = np.random.default_rng(i).integers(0, 256, (40, 56, 3), np.uint8)
        cv2.imwrite(str(tmp_path / "in" / f"p{i}.png"), image)
    proc = cli("batch", "in/*.png", "--ops", "comb-wave", "-o", "out/{stem}.png", "--time", "1",
               "--cluster", "ray", env={"RAY_ADDRESS": cluster})  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "3 written" in proc.stderr
    assert files(tmp_path / "out") == [MANIFEST_NAME, "p0.png", "p1.png", "p2.png"]
    for i in range(3):
        api.render_still(tmp_path / "in" / f"p{i}.png", "comb-wave", tmp_path / "s.png",
                         time=1, overwrite=True)  # fmt: skip
        read = [cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
                for p in (tmp_path / "out" / f"p{i}.png", tmp_path / "s.png")]  # fmt: skip
        assert np.array_equal(*read), i
