"""`marblevideo export` to ffmpeg: the .cl file run by the real ffmpeg (Debian's, with
OpenCL) on the test machine's OpenCL device, `program_opencl` over an RGBA frame
sequence and `openclsrc` for blank sheets, each frame against the NumPy reference of
the recipe at index / fps."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import av
import cv2
import numpy as np
import pytest
from clips import probe
from helpers import ROOT
from recipes import make_image, random_recipe
from tolerances import LOSSY_MEAN_RESAMPLED

from marblevideo import reference
from marblevideo.bundled import preset_path
from marblevideo.cli import main
from marblevideo.recipe.frame import geometry
from marblevideo.recipe.load import parse_recipe

pytestmark = [
    pytest.mark.tier("integration"),
    pytest.mark.skipif(
        shutil.which("ffmpeg") is None and not os.environ.get("CI"), reason="needs ffmpeg"
    ),
]

#: ffmpeg's frames against the reference: this share of pixels within LEVELS.
LEVELS, SHARE = 6, 0.99
#: Frames each case runs, and the rate they are exported for.
FRAMES, FPS = 4, 1.5


def ffmpeg(*args: str) -> None:
    cmd = ["ffmpeg", "-v", "error", "-nostdin", "-init_hw_device", "opencl=ocl"]
    done = subprocess.run([*cmd, "-filter_hw_device", "ocl", *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def export(recipe: dict, folder: Path, fps: float = FPS, *options: str) -> Path:
    src, out = folder / "recipe.json", folder / "recipe.cl"
    src.write_text(json.dumps(recipe))
    argv = ["export", str(src), "-o", str(out), "--fps", f"{fps!r}", "-q", "-y", *options]
    assert main(argv) == 0
    return out


def read_frames(folder: Path, n: int) -> list[np.ndarray]:
    frames = [cv2.imread(str(folder / f"{k:03d}.png"), cv2.IMREAD_UNCHANGED) for k in range(n)]
    return [cv2.cvtColor(f, cv2.COLOR_BGRA2RGBA) for f in frames]


def agreement(got: np.ndarray, want: np.ndarray) -> float:
    """The share of pixels within LEVELS in every channel."""
    diff = np.abs(got.astype(int) - want.astype(int)).max(axis=2)
    return float((diff <= LEVELS).mean())


def filtered(recipe: dict, folder: Path, w: int = 72, h: int = 54, iw: int | None = None):
    """(ffmpeg's frames, the reference's) of ``recipe`` over FRAMES input pictures of
    iw x (iw * h / w) scaled to w x h by the filter graph (or w x h as they are)."""
    cl = export(recipe, folder)
    (folder / "in").mkdir()
    (folder / "out").mkdir()
    iw = iw or w
    ih = iw * h // w
    pictures = [make_image(iw, ih, seed=k) for k in range(FRAMES)]
    for k, picture in enumerate(pictures):
        cv2.imwrite(str(folder / "in" / f"{k:03d}.png"), cv2.cvtColor(picture, cv2.COLOR_RGBA2BGRA))
    ffmpeg(
        "-framerate", "30", "-i", str(folder / "in" / "%03d.png"),
        "-vf", f"format=rgba,hwupload,program_opencl=source={cl}:kernel=marble:size={w}x{h},"
        "hwdownload,format=rgba",
        "-start_number", "0", str(folder / "out" / "%03d.png"),
    )  # fmt: skip
    r = parse_recipe(recipe)
    canvas = r.canvas or (iw, ih)
    want = [
        reference.render(r.at(k / FPS, canvas), geometry(canvas, (w, h), (iw, ih)), pictures[k])
        for k in range(FRAMES)
    ]
    return read_frames(folder / "out", FRAMES), want


def sheet(
    recipe: dict, folder: Path, w: int, h: int, fps: float = FPS, frames: int = FRAMES, *options
):
    """(ffmpeg's frames, the reference's) of ``recipe`` on a w x h blank sheet
    (``options``: more of the export's)."""
    cl = export(recipe, folder, fps, *options)
    (folder / "out").mkdir()
    ffmpeg(
        "-filter_complex",
        f"openclsrc=source={cl}:kernel=marble_sheet:size={w}x{h}:format=rgba:rate={fps!r},"
        "hwdownload,format=rgba",
        "-frames:v", str(frames), "-start_number", "0", str(folder / "out" / "%03d.png"),
    )  # fmt: skip
    r = parse_recipe(recipe)
    canvas = r.canvas or (w, h)
    want = [
        reference.render(r.at(k / fps, canvas), geometry(canvas, (w, h)))[..., :3]
        for k in range(frames)
    ]
    got = [f[..., :3] for f in read_frames(folder / "out", frames)]
    return got, want


def assert_agrees(got: list[np.ndarray], want: list[np.ndarray]) -> None:
    for k, (g, w) in enumerate(zip(got, want, strict=True)):
        assert g.shape == w.shape
        share = agreement(g, w)
        assert share >= SHARE, f"frame {k}: {share:.2%} of pixels within {LEVELS} levels"


@pytest.mark.parametrize("seed", [3, 8, 13])
def test_random_recipes_over_frames(tmp_path, seed):
    """Random recipes of every op type (keyed, eased, started and ended; each seed
    another pattern and edges mode) through program_opencl, against the reference."""
    assert_agrees(*filtered(random_recipe(seed, 160, 120), tmp_path))


def test_a_recipe_without_canvas_takes_the_input_and_the_output_may_differ(tmp_path):
    """No canvas: ops in the input's pixels; the input scaled by the filter graph's
    size= (the canvas fitted into the output, the input stretched over it)."""
    recipe = random_recipe(21, 96, 64)
    del recipe["canvas"]
    assert_agrees(*filtered(recipe, tmp_path, w=80, h=60, iw=96))


@pytest.mark.parametrize("seed", [4, 11])
def test_random_blank_sheets(tmp_path, seed):
    """openclsrc: a blank sheet of a random recipe (ink first), in a frame of
    another aspect than its canvas (fitted and centred)."""
    assert_agrees(*sheet(random_recipe(seed, 160, 120, blank=True), tmp_path, 90, 50))


def test_timed_strokes_and_a_keyed_background(tmp_path):
    """A stroke drawn in time (its steps laid frame by frame) beside an untimed one,
    on a background that is keyed."""
    recipe = {
        "marblevideo": 1,
        "canvas": [120, 80],
        "background": {"keys": [{"t": 0, "v": "#203040"}, {"t": 2, "v": "#e0c080"}]},
        "ops": [
            {"type": "drop", "center": [60, 40], "radius": 30, "color": "#c03020"},
            {"type": "drop", "center": [60, 40], "radius": 15, "color": "#f0f0f0"},
            {
                "type": "stroke",
                "points": [[10, 20], [60, 50], [110, 30]],
                "times": [0, 1, 2],
                "width": 12,
            },
            {"type": "stroke", "points": [[20, 70], [100, 10]], "width": 8},
        ],
    }
    assert_agrees(*sheet(recipe, tmp_path, 120, 80, fps=2.0, frames=6))


def test_a_preset_at_its_end_and_after(tmp_path):
    """nonpareil (a layout of drops, combed): the frames past the recipe's end hold
    its last frame."""
    recipe = json.loads(preset_path("nonpareil").read_text())
    r = parse_recipe(recipe)
    fps = 0.25
    frames = int(r.settled_time() * fps) + 3
    got, want = sheet(recipe, tmp_path, 96, 64, fps=fps, frames=frames)
    assert_agrees(got, want)
    assert np.array_equal(got[-1], got[-2])


def test_more_constant_memory_for_a_device_that_has_it(tmp_path):
    """bird (a stroke drawn in time over 54 drops) needs more than 64 KiB at 30 fps:
    refused by default, exported with --constant-memory for PoCL's 2 MiB, and run."""
    recipe = json.loads(preset_path("bird").read_text())
    assert main(["export", "bird", "-o", str(tmp_path / "bird.cl"), "-q"]) == 2
    more = ("--constant-memory", "1000000")
    assert_agrees(*sheet(recipe, tmp_path, 96, 64, 30.0, 3, *more))


def test_refusals_say_one_line_and_write_nothing(tmp_path, capsys):
    """What a .cl file cannot carry, and bad options: one line, exit 2, nothing written."""
    out = tmp_path / "x.cl"
    cases = [
        (["export", "dance", "-o", str(out)], "motion: camera motion"),
        (["export", "pulse", "-o", str(out)], "follows a signal"),
        (["export", "swirl", "-o", str(tmp_path / "x.txt")], "unknown export extension '.txt'"),
        (["export", "swirl", "-o", str(out), "--fps", "0"], "--fps: expected"),
        (["export", "swirl", "-o", str(out), "--fps", "nan"], "--fps: expected"),
        (["export", "swirl", "-o", str(out), "--fps", "1000"], "bytes of constant memory"),
        (["export", str(tmp_path / "none.json"), "-o", str(out)], "cannot read recipe"),
        (["export", "swirl", "-o", str(tmp_path)], "output is a folder"),
        (["export", "bird", "-o", str(out), "--constant-memory", "100"], "--constant-memory"),
    ]
    for argv, text in cases:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and text in err[0], (argv, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    assert main(["export", "swirl", "-o", str(out), "-q"]) == 0
    before = out.read_bytes()
    assert main(["export", "tile", "-o", str(out), "-q"]) == 2
    assert "already exists" in capsys.readouterr().err
    assert out.read_bytes() == before


def test_generated_code_holds_numbers_only(tmp_path):
    """A recipe whose text fields look like code: none of it reaches the .cl file."""
    recipe = random_recipe(5, 160, 120)
    recipe["description"] = '*/ #include "/etc/q7z" __kernel void evil_q7z() {} /*'
    text = export(recipe, tmp_path).read_text()
    assert "q7z" not in text


def documented_commands(cl: Path) -> list[str]:
    """The ffmpeg commands of the .cl file's first comment, as a shell reads them."""
    comment = cl.read_text().split("*/", 1)[0].splitlines()
    commands, current = [], None
    for line in comment:
        text = line[3:] if line.startswith(" * ") else line
        if text.lstrip().startswith("ffmpeg "):
            current = [text.strip()]
        elif current is not None:
            current.append(text.strip())
        if current is not None and not text.endswith("\\"):
            commands.append("\n".join(current))
            current = None
    return commands


def test_the_commands_the_file_documents_run(tmp_path):
    """The file's own two commands, as written (the sheet smaller), over the bundled
    clip (25 fps, with sound): every frame marbled as the reference marbles it (a
    lossy encode's difference) and the audio kept; the sheet has the frames it says."""
    shutil.copy(ROOT / "samples" / "coffee.mp4", tmp_path / "in.mp4")
    cl = tmp_path / "swirl.cl"
    assert main(["export", "swirl", "-o", str(cl), "--fps", "25", "-q"]) == 0
    filter_cmd, sheet_cmd = documented_commands(cl)
    for cmd in (filter_cmd, sheet_cmd.replace("1280x720", "64x36")):
        cmd = cmd.replace("FILE.cl", cl.name)
        done = subprocess.run(
            ["bash", "-c", cmd],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            stdin=subprocess.DEVNULL,
        )
        assert done.returncode == 0, (cmd, done.stderr[-2000:])
    marbled, source = probe(tmp_path / "out.mp4"), probe(tmp_path / "in.mp4")
    assert len(marbled.frames) == len(source.frames) and marbled.audio_packets
    assert marbled.audio_packets == source.audio_packets  # -c:a copy: the sound as it was
    swirl = parse_recipe(json.loads(preset_path("swirl").read_text()))
    geom = geometry(swirl.canvas, (480, 270), (480, 270))
    want = reference.render(swirl.at(75 / 25), geom, source.frames[75]).astype(int)
    off = np.abs(marbled.frames[75].astype(int) - want).mean()
    assert off <= LOSSY_MEAN_RESAMPLED < np.abs(source.frames[75].astype(int) - want).mean()
    with av.open(str(tmp_path / "sheet.mp4")) as sheet_file:  # the frames the file holds
        assert sheet_file.streams.video[0].frames == math.ceil(swirl.settled_time() * 25) + 1


def test_the_commands_of_docs_export_run(tmp_path):
    """docs/export.md's ```sh blocks that run a host, as bash runs them (the exports,
    then the real ffmpeg or GStreamer, under Xvfb), from a folder with the samples,
    the sheet smaller and shorter: each writes its video."""
    (tmp_path / "samples").symlink_to(ROOT / "samples")
    env = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
        "XDG_RUNTIME_DIR": str(tmp_path),
    }
    blocks = re.findall(r"```sh\n(.*?)```", (ROOT / "docs" / "export.md").read_text(), re.S)
    ran = 0
    for block in blocks:
        if "ffmpeg " not in block and "gst-launch-1.0" not in block:
            continue
        script = re.sub(r"size=\d+x\d+", "size=48x32", block)
        script = re.sub(r"-frames:v \d+", "-frames:v 20", script)
        argv = ["bash", "-euc", script]
        if "gst-launch-1.0" in block:
            argv = ["xvfb-run", "-a", *argv]
        done = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, timeout=600)
        assert done.returncode == 0, done.stderr[-2000:]
        written = block.split()[-1].removeprefix("location=")
        with av.open(str(tmp_path / written)) as video:
            assert sum(1 for _ in video.decode(video=0)) >= 20
        ran += 1
    assert ran == 3
