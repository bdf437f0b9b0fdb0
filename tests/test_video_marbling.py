"""Marbled video end to end: the real CLI and API on generated clips.

Frames are checked against the NumPy reference at their own timestamps; the
encoded file against the frames the renderer produced; timing and audio
against the input.
"""

from __future__ import annotations

import json
import math
from fractions import Fraction

import numpy as np
import pytest
from clips import probe, write_clip
from helpers import fresh_renderer
from tolerances import KERNEL_LEVELS, KERNEL_SHARE

from marblevideo.api import marbled_frames
from marblevideo.jobs.pipeline import iter_frames
from marblevideo.recipe import load_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("integration")

RECIPE = {
    "marblevideo": 1,
    "canvas": [160, 120],
    "antialias": "rgss",
    "edges": "mirror",
    "ops": [
        {
            "type": "drop",
            "center": [80, 60],
            "radius": 18,
            "color": "#b23a48",
            "start": 0.2,
            "end": 0.8,
        },
        {
            "type": "comb",
            "point": [0, 0],
            "angle": 90,
            "spacing": 40,
            "lambda": 6,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 1, "v": 25, "ease": "ease-in-out"}]},
        },
        {
            "type": "vortex",
            "center": [80, 60],
            "lambda": 30,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 1.2, "v": 120}]},
        },
    ],
}


def _recipe_file(tmp_path):
    path = tmp_path / "swirl.json"
    path.write_text(json.dumps(RECIPE))
    return path


def _psnr(a: np.ndarray, b: np.ndarray) -> float:
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return 99.0 if mse == 0 else 10 * math.log10(255.0**2 / mse)


def test_frames_match_the_reference_at_their_timestamps(tmp_path):
    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=30, fps=25, audio=False)
    recipe = load_recipe(_recipe_file(tmp_path))
    inputs = dict(iter_frames(clip))
    seen = 0
    for t, ours in marbled_frames(clip, recipe):
        image = inputs[t]
        spec = recipe.at(t, None)
        ref = reference_render(spec, geometry(recipe.canvas, (96, 64), (96, 64)), image)
        diff = np.abs(ours.astype(np.int16) - ref.astype(np.int16)).max(axis=2)
        assert (diff <= KERNEL_LEVELS).mean() >= KERNEL_SHARE, f"frame at t={t}"
        seen += 1
    assert seen == 30
    first, second = (f for _, f in marbled_frames(clip, recipe, start=0.0, end=0.05))
    assert not np.array_equal(first, second)  # the animation moves between frames


def test_cli_keeps_timing_and_audio_and_encodes_the_marbled_frames(tmp_path, cli):
    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=25, fps=25, audio=True)
    recipe = _recipe_file(tmp_path)
    run = cli(clip, "--ops", recipe, "-o", "out.mp4", "--crf", "12", "--pix-fmt", "yuv444p")
    assert run.returncode == 0, run.stderr
    src, out = probe(clip), probe(tmp_path / "out.mp4")
    assert out.pts == src.pts and out.time_base == src.time_base
    assert out.audio_packets == src.audio_packets  # bit-exact copy
    assert out.codec == "h264" and (out.width, out.height) == (96, 64)
    expected = [f[:, :, :3] for _, f in marbled_frames(clip, load_recipe(recipe))]
    for ours, want in zip(out.frames, expected, strict=True):
        assert _psnr(ours, want) > 35


def test_cli_blank_sheet_renders_the_process(tmp_path, cli):
    recipe = _recipe_file(tmp_path)
    run = cli("--ops", recipe, "-o", "process.webm", "--fps", "10", "-q")
    assert run.returncode == 0, run.stderr
    out = probe(tmp_path / "process.webm")
    end = load_recipe(recipe).end_time()
    assert len(out.frames) == math.ceil((end + 1.0) * 10)
    assert out.codec == "vp9" and (out.width, out.height) == (160, 120)
    assert out.audio_codec is None
    assert not np.array_equal(out.frames[0], out.frames[-1])


def test_cli_range_size_and_progress_json(tmp_path, cli):
    clip = write_clip(
        tmp_path / "in.mkv", size=(96, 64), frames=40, fps=20, time_base=Fraction(1, 1000)
    )
    run = cli(
        clip,
        "--ops",
        _recipe_file(tmp_path),
        "-o",
        "part.mkv",
        "--start",
        "0.5",
        "--end",
        "1.5",
        "--size",
        "64x48",
        "--progress",
        "json",
    )
    assert run.returncode == 0, run.stderr
    out = probe(tmp_path / "part.mkv")
    assert len(out.frames) == 20 and (out.width, out.height) == (64, 48)
    lines = [json.loads(line) for line in run.stderr.splitlines() if line.startswith("{")]
    assert lines and lines[-1]["frame"] == 20


def test_a_static_recipe_keeps_its_maps_from_the_first_frame(tmp_path):
    """A recipe without keyframes lands every frame where the first did: the video
    transform draws even the first frame from the table of reused maps."""
    from marblevideo.marbler import Marbler

    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=3, fps=25, audio=False)
    static = {**RECIPE, "ops": [{**RECIPE["ops"][1], "alpha": 20}]}
    for recipe, expect_static in ((static, True), (RECIPE, False)):
        marbler = Marbler(recipe, fresh_renderer())  # fresh: no table filled before
        transform = marbler.transform()
        assert transform.route.static is expect_static
        for t, image in iter_frames(clip):
            ours = transform(image, t)
            assert marbler.renderer.last_reused is expect_static  # animated: new maps
            spec = marbler.recipe.at(t, None)
            ref = reference_render(spec, geometry(RECIPE["canvas"], (96, 64), (96, 64)), image)
            diff = np.abs(ours.astype(np.int16) - ref.astype(np.int16)).max(axis=2)
            assert (diff <= KERNEL_LEVELS).mean() >= KERNEL_SHARE
