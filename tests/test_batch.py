"""``marblevideo batch``: many inputs through one recipe, on real files, serially
and on a local process pool; resuming from the manifest; usage errors."""

from __future__ import annotations

import json
import signal
import subprocess
import sys

import cv2
import numpy as np
import pytest
from clips import probe, write_clip
from helpers import files, one_line, subprocess_env
from interrupts import interrupt, wait_until

from marblevideo import api
from marblevideo.scale.batch import MANIFEST_NAME, run_batch

pytestmark = pytest.mark.tier("integration")


@pytest.fixture
def photos(tmp_path):
    (tmp_path / "in").mkdir()
    (tmp_path / "out").mkdir()
    for i in range(4):
        rng = np.random.default_rng(i)
        cv2.imwrite(str(tmp_path / "in" / f"p{i}.jpg"), rng.integers(0, 256, (48, 64, 3), np.uint8))
    return tmp_path


def _same(a, b) -> bool:
    return np.array_equal(
        cv2.imread(str(a), cv2.IMREAD_UNCHANGED), cv2.imread(str(b), cv2.IMREAD_UNCHANGED)
    )


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_batch_equals_single_renders(cli, photos, jobs):
    proc = cli("batch", "in/*.jpg", "--ops", "comb-wave", "-o", "out/{stem}-{index:02d}.png",
               "--jobs", jobs, "--time", "1")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "4 written" in proc.stderr
    assert files(photos / "out") == [MANIFEST_NAME] + [f"p{i}-{i:02d}.png" for i in range(4)]
    for i in range(4):
        single = photos / f"single{i}.png"
        api.render_still(photos / "in" / f"p{i}.jpg", "comb-wave", single, time=1)
        assert _same(photos / "out" / f"p{i}-{i:02d}.png", single), i


def test_a_failed_item_is_named_and_the_rerun_resumes(cli, photos):
    (photos / "in" / "p2.jpg").write_bytes(b"not a picture" * 40)
    proc = cli("batch", "in/*.jpg", "--ops", "comb-wave", "-o", "out/{stem}.png", "-q")
    assert proc.returncode == 1
    assert "3 written, 1 failed" in one_line(proc) and "p2.jpg" in one_line(proc)
    assert files(photos / "out") == [MANIFEST_NAME, "p0.png", "p1.png", "p3.png"]
    record = json.loads((photos / "out" / MANIFEST_NAME).read_text())["items"]
    assert record["out/p2.png"]["status"] == "failed" and record["out/p0.png"]["status"] == "done"
    before = {n: (photos / "out" / n).stat().st_mtime_ns for n in ("p0.png", "p1.png", "p3.png")}
    rng = np.random.default_rng(2)
    cv2.imwrite(str(photos / "in" / "p2.jpg"), rng.integers(0, 256, (48, 64, 3), np.uint8))
    again = cli("batch", "in/*.jpg", "--ops", "comb-wave", "-o", "out/{stem}.png", "-y")
    assert again.returncode == 0, again.stderr
    assert "1 of 4 to render; 3 done before" in again.stderr
    assert "1 written, 3 done before" in again.stderr.splitlines()[-1]
    after = {n: (photos / "out" / n).stat().st_mtime_ns for n in before}
    assert after == before  # done before, even with -y: not rendered again


def test_existing_outputs_and_a_changed_recipe(cli, photos):
    (photos / "out" / "p1.png").write_bytes(b"someone else's file")
    proc = cli("batch", "in/*.jpg", "--ops", "comb-wave", "-o", "out/{stem}.png")
    assert proc.returncode == 0, proc.stderr
    assert "1 existing skipped (use -y to replace)" in proc.stderr
    assert (photos / "out" / "p1.png").read_bytes() == b"someone else's file"
    # another recipe (or other options) is another job: -y renders every item again
    proc = cli("batch", "in/*.jpg", "--ops", "swirl", "-o", "out/{stem}.png", "-y")
    assert proc.returncode == 0 and "4 written" in proc.stderr, proc.stderr
    api.render_still(photos / "in" / "p1.jpg", "swirl", photos / "single.png")
    assert _same(photos / "out" / "p1.png", photos / "single.png")


def test_videos_in_a_batch(tmp_path):
    for name in ("a", "b"):
        write_clip(tmp_path / f"{name}.mp4", size=(64, 48), frames=6, fps=12, audio=True)
    result = run_batch([str(tmp_path / "*.mp4")], "swirl", str(tmp_path / "{stem}-m.mkv"),
                       progress="off")  # fmt: skip
    assert sorted(p.name for p in result.written) == ["a-m.mkv", "b-m.mkv"]
    for name in ("a", "b"):
        out = probe(tmp_path / f"{name}-m.mkv")
        assert (
            len(out.frames) == 6
            and out.audio_packets == probe(tmp_path / f"{name}.mp4").audio_packets
        )


@pytest.mark.parametrize(
    "args, fault",
    [
        (["in/*.jpg", "-o", "out/{bad}.png"], "unknown field {bad}"),
        (["in/*.jpg", "-o", "out/all.png"], "name each output from its input"),
        (["in/*.jpg", "-o", "out/{suffix}.png"], "would both write"),
        (["nothing/*.jpg", "-o", "out/{stem}.png"], "matches no file"),
        (["in/*.jpg", "-o", "in/p0.jpg/{stem}.png"], "in/p0.jpg is a file"),
        (["in/*.jpg", "-o", "out/{name}/{stem}.png"], "out/p0.jpg is a file"),
        (["in/*.jpg", "-o", "in/{stem}.jpg"], "is one of the inputs"),
        (["in/*.jpg", "-o", "out/{stem}.xyz"], "unknown output extension '.xyz'; use stills"),
        (["in/*.jpg", "-o", "out/{stem}.svg"], "not .svg vectors"),
        (["in/*.jpg", "-o", "out/{stem}.png", "--jobs", "0"], "--jobs"),
        (["in/*.jpg", "-o", "out/{stem}.mp4", "--time", "1"], "--time: applies to still outputs"),
        (["in/*.jpg", "-o", "out/{stem}.png", "--ops", "nopreset"], "nor a preset"),
    ],
)
def test_usage_errors_before_any_work(cli, photos, args, fault):
    (photos / "out" / "p0.jpg").write_bytes(b"a file where a folder would go")
    ops = [] if "--ops" in args else ["--ops", "comb-wave"]
    proc = cli("batch", *args, *ops)
    assert proc.returncode == 2, proc.stderr
    assert fault in one_line(proc)
    assert files(photos / "out") == ["p0.jpg"]
    assert files(photos / "in") == [f"p{i}.jpg" for i in range(4)]


def test_templates_make_their_folders(cli, photos):
    """Folders a template names (fixed parts and {parent}) are made, each output
    still written atomically inside them; the manifest lands beside the first."""
    (photos / "in" / "sub").mkdir()
    cv2.imwrite(str(photos / "in" / "sub" / "q.png"), np.full((32, 40, 3), 90, np.uint8))
    proc = cli("batch", "in/**/*.*g", "--ops", "comb-wave", "-o", "made/{parent}/{stem}/x.png")
    assert proc.returncode == 0, proc.stderr
    assert "5 written" in proc.stderr.splitlines()[-1]
    assert files(photos / "made" / "in" / "p0") == [MANIFEST_NAME, "x.png"]
    for stem in ("p1", "p2", "p3", "sub/q"):
        assert files(photos / "made" / "in" / stem) == ["x.png"]
    single = photos / "single.png"
    api.render_still(photos / "in" / "sub" / "q.png", "comb-wave", single)
    assert _same(photos / "made" / "in" / "sub" / "q" / "x.png", single)


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupting_a_batch_on_workers(tmp_path, sig, code):
    """A signal to the batch (as a process manager sends it, to the main process
    only) stops its workers too: out soon, one line, no temporary file, and every
    output there is recorded done, so a re-run resumes."""
    (tmp_path / "in").mkdir()
    for i in range(8):
        cv2.imwrite(str(tmp_path / "in" / f"p{i}.jpg"), np.full((30, 40, 3), 20 * i, np.uint8))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "marblevideo",
            "batch",
            "in/*.jpg",
            "--ops",
            "swirl",
            "-o",
            "out/{stem}.png",
            "--size",
            "2400x1800",
            "--jobs",
            "2",
            "-q",
        ],  # fmt: skip
        cwd=tmp_path,
        stderr=subprocess.PIPE,
        text=True,
        env=subprocess_env(),
    )
    manifest = tmp_path / "out" / MANIFEST_NAME
    wait_until(proc, manifest.exists, 180)
    done = interrupt(proc, sig)
    assert done.returncode == code
    assert done.stderr.splitlines() == ["marblevideo: interrupted"]
    written = sorted(f"out/{p.name}" for p in (tmp_path / "out").glob("*.png"))
    record = json.loads(manifest.read_text())["items"]
    assert sorted(k for k, v in record.items() if v["status"] == "done") == written
    assert 0 < len(written) < 8
    assert [p.name for p in (tmp_path / "out").iterdir() if ".part" in p.name] == []
