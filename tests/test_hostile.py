"""Bad input never crashes and never loses data.

Extreme but valid recipes, broken media, hostile outputs (full disk, read-only
folder, the input itself), interrupts and OpenCL faults, each through the real
code: the command line in a subprocess where the exit status and stderr are
the contract, the session renderer otherwise. Every failure must be one stderr
line and the documented exit status (README: 0 done, 1 runtime failure, 2 usage
or recipe error, 130/143 interrupted), with the input untouched and no output
or temporary file left behind.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import signal
import struct
import subprocess
import sys
import time
import zlib
from pathlib import Path

import cv2
import numpy as np
import pytest
from clips import write_clip
from helpers import ROOT, files, fresh_renderer, one_line, run_main, subprocess_env
from interrupts import interrupt
from recipes import make_image

from marblevideo.cli.render import _render_parser
from marblevideo.errors import DeviceError, UsageError
from marblevideo.media.images import MAX_PIXELS
from marblevideo.opencl.program import Structure
from marblevideo.opencl.renderer import MAX_SIDE
from marblevideo.opencl.selfcheck import agreement
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("integration")

CANVAS = {"canvas": [64, 48], "antialias": "none"}


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def leftovers(folder: Path) -> list[str]:
    """Temporary files of marblevideo.media.output (.NAME.XXXX.part.EXT)."""
    return sorted(p.name for p in folder.iterdir() if ".part" in p.name)


@pytest.fixture
def recipe(tmp_path) -> Path:
    path = tmp_path / "r.json"
    ops = [{"type": "vortex", "center": [32, 24], "alpha": 40, "lambda": 10}]
    path.write_text(json.dumps({"antialias": "none", "ops": ops}))
    return path


@pytest.fixture
def blank(tmp_path) -> Path:
    path = tmp_path / "blank.json"
    ops = [{"type": "drop", "center": [32, 24], "radius": 9, "color": "#2255aa"}]
    path.write_text(json.dumps({**CANVAS, "ops": ops}))
    return path


# ---------------------------------------------------------------------------- extreme values


def against_reference(renderer, doc: dict, size=(32, 24), image=None, share=0.97):
    recipe = parse_recipe(doc, "extreme.json")
    spec = recipe.at(recipe.end_time())
    input_size = None if image is None else (image.shape[1], image.shape[0])
    geom = geometry(recipe.canvas, size, input_size)
    ours = renderer.render(spec, geom, image)
    again = renderer.render(spec, geom, image)  # over an input: from the reused maps
    if image is None:
        assert np.array_equal(ours, again)  # deterministic
    else:
        assert renderer.last_reused and agreement(ours, again, levels=1) == 1.0
    ref = reference_render(spec, geom, image)
    for out in (ours, again):
        assert agreement(out, ref) >= share, agreement(out, ref)
    return ours


# (op, share of pixels within 4 levels of the float64 reference): float32 loses the
# last digits where a vortex turns 1e4+ times or a comb shifts by 1e6 spacings.
EXTREME = [
    ({"type": "tine", "point": [0, 24], "angle": 30, "alpha": 1e6, "lambda": 4}, 0.97),
    ({"type": "tine", "point": [0, 24], "angle": 0, "alpha": 40, "lambda": 1e-6}, 0.97),
    (
        {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 1e-3, "alpha": 5, "lambda": 2},
        0.97,
    ),
    (
        {"type": "comb", "point": [0, 0], "angle": 0, "spacing": 1e5, "alpha": 1e6, "lambda": 1e5},
        0.93,
    ),
    ({"type": "drop", "center": [32, 24], "radius": 1e5, "color": [10, 200, 30]}, 0.97),
    ({"type": "drop", "center": [32, 24], "radius": 1e-6, "color": [10, 200, 30]}, 0.97),
    ({"type": "circle", "center": [32, 24], "radius": 1e5, "alpha": 1e6, "lambda": 1e-6}, 0.97),
    ({"type": "vortex", "center": [32, 24], "alpha": 1e6, "lambda": 1e5}, 0.93),
    ({"type": "wave", "amplitude": 1e6, "wavelength": 1e5, "phase": 0, "angle": 0}, 0.97),
]


@pytest.mark.parametrize("op, share", EXTREME, ids=[op["type"] for op, _ in EXTREME])
def test_extreme_values_match_the_reference(renderer, op, share):
    image = make_image(40, 30, 5)
    doc = {**CANVAS, "edges": "mirror", "ops": [op]}
    against_reference(renderer, doc, image=image, share=share)


@pytest.mark.parametrize("alpha", [1e10, -1e29])
def test_vortex_past_float32_turns_does_not_collapse(renderer, alpha):
    """alpha * lambda / R of 1e9+ turns has no fractional part in float32: the kernel
    must still rotate by *some* angle, not collapse every point to the centre (a bug:
    cos came from turns + 0.25, which rounds back to turns)."""
    doc = {
        **CANVAS,
        "ops": [{"type": "vortex", "center": [32, 24], "alpha": alpha, "lambda": 1e10}],
    }
    recipe = parse_recipe(doc, "vortex.json")
    geom = geometry(recipe.canvas, (32, 24), (40, 30))
    out = renderer.render(recipe.at(0), geom, make_image(40, 30, 5))
    assert len(np.unique(out.reshape(-1, 4), axis=0)) > 50


def test_tiny_wavelength_renders_plausible_colors(renderer):
    """A 1e-3 wavelength aliases (float32 cannot follow it): no crash, no NaN garbage:
    every pixel is one of the input's colors or between neighbours."""
    image = np.zeros((30, 40, 3), np.uint8)
    image[:, 20:] = (200, 100, 50)
    doc = {
        **CANVAS,
        "ops": [{"type": "wave", "amplitude": 30, "wavelength": 1e-3, "phase": 0, "angle": 90}],
    }
    recipe = parse_recipe(doc, "wave.json")
    geom = geometry(recipe.canvas, (32, 24), (40, 30))
    out = renderer.render(recipe.at(0), geom, image)
    assert np.array_equal(out, renderer.render(recipe.at(0), geom, image))
    assert (out[..., 3] == 255).all()
    share = out[..., :3].astype(float) / np.array([200, 100, 50])  # on the line 0 -> color
    assert np.allclose(share, share[..., :1], atol=0.02)


def test_three_thousand_ops_match_the_reference(renderer):
    """Far past the unrolled limit (48): the loop walk, compared with the reference."""
    rng = np.random.default_rng(11)
    ops = []
    for i in range(3000):
        x, y = (float(v) for v in rng.uniform(0, 64, 2))
        if i % 3 == 0:
            ops.append(
                {"type": "drop", "center": [x, y], "radius": 1.5, "color": [i % 256, 90, 40]}
            )
        elif i % 3 == 1:
            ops.append(
                {"type": "tine", "point": [x, y], "angle": i % 180, "alpha": 0.3, "lambda": 3}
            )
        else:
            ops.append({"type": "vortex", "center": [x, y], "alpha": 0.2, "lambda": 4})
    out = against_reference(renderer, {**CANVAS, "ops": ops}, share=0.9)
    assert len(np.unique(out.reshape(-1, 4), axis=0)) > 20  # a pattern, not a flat field


def test_too_large_output_side_is_refused(renderer):
    recipe = parse_recipe({**CANVAS, "ops": []}, "r.json")
    with pytest.raises(ValueError, match=str(MAX_SIDE)):
        renderer.render(recipe.at(0), geometry(recipe.canvas, (MAX_SIDE + 1, 4), None))


def test_allocation_failure_is_a_device_error(renderer):
    """An output bigger than the device's largest buffer: a DeviceError, one line."""
    side = MAX_SIDE
    if side * side * 4 <= renderer.info.device.max_mem_alloc_size:
        pytest.skip("this device can allocate a 32768x32768 RGBA buffer")
    recipe = parse_recipe({**CANVAS, "ops": []}, "r.json")
    with pytest.raises(DeviceError, match="cannot allocate") as info:
        renderer.render(recipe.at(0), geometry(recipe.canvas, (side, side), None))
    assert "\n" not in str(info.value)


# ---------------------------------------------------------------------------- media faults


def _png_header_only(path: Path, width: int, height: int) -> Path:
    def chunk(kind: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    idat = zlib.compress(b"\0" * 64)
    path.write_bytes(
        b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")
    )
    return path


# The command's own peak (VmHWM, KB): ru_maxrss would also count the pytest process it
# was forked from (Linux keeps the pre-exec peak), over 1 GB late in a whole run.
MEASURED = (
    "import re, sys; from marblevideo.cli import main; code = main(sys.argv[1:]);"
    "status = open('/proc/self/status').read();"
    "print(re.search(r'VmHWM:\\s+(\\d+)', status).group(1), file=sys.stderr); sys.exit(code)"
)


def test_image_claiming_100000_squared_pixels_is_refused_from_its_header(tmp_path, recipe):
    """Refused before any pixel is allocated: fast, and peak memory far below 30 GB."""
    _png_header_only(tmp_path / "huge.png", 100_000, 100_000)
    began = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-c", MEASURED, "huge.png", "--ops", "r.json", "-o", "o.png"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
        env=subprocess_env(),
    )
    assert time.monotonic() - began < 20
    *message, peak_kb = proc.stderr.splitlines()
    assert proc.returncode == 1 and len(message) == 1, proc.stderr
    assert message[0] == f"marblevideo: huge.png: image is over the limit of {MAX_PIXELS} pixels"
    assert int(peak_kb) < 1_000_000  # KB: far below the 30 GB the header asks for
    assert sorted(os.listdir(tmp_path)) == ["huge.png", "r.json"]


def test_sixteen_bit_grey_png_is_converted(cli, tmp_path, recipe):
    grey = (np.arange(48 * 64, dtype=np.uint32).reshape(48, 64) * 21).astype(np.uint16)
    cv2.imwrite(str(tmp_path / "g16.png"), grey)
    proc = cli("g16.png", "--ops", "r.json", "-o", "o.png", "-q")
    assert proc.returncode == 0 and proc.stderr == ""
    out = cv2.imread(str(tmp_path / "o.png"), cv2.IMREAD_UNCHANGED)
    assert out.shape == (48, 64, 3) and out.dtype == np.uint8
    assert (out[..., 0] == out[..., 1]).all() and out.max() > 200  # still grey, not clipped


@pytest.fixture(scope="module")
def clip(tmp_path_factory) -> Path:
    return write_clip(tmp_path_factory.mktemp("media") / "clip.mp4", frames=20)


def _media_cases(folder: Path, clip: Path) -> dict[str, tuple[str, int, str]]:
    """name -> (file, exit status, part of the message)."""
    (folder / "empty.mp4").write_bytes(b"")
    (folder / "empty.png").write_bytes(b"")
    (folder / "text.mp4").write_text("this is not a video\n" * 50)
    (folder / "text.png").write_text("this is not a picture\n" * 50)
    (folder / "dir.mp4").mkdir()
    (folder / "dir.png").mkdir()
    data = clip.read_bytes()
    (folder / "half.mp4").write_bytes(data[: len(data) // 2])
    (folder / "head.mp4").write_bytes(data[:200])
    with av_audio_only(folder / "audio.mp4"):
        pass
    return {
        "missing video": ("nope.mp4", 1, "no such file"),
        "missing image": ("nope.png", 1, "no such file"),
        "folder video": ("dir.mp4", 1, "folder"),
        "folder image": ("dir.png", 1, "folder"),
        "empty video": ("empty.mp4", 1, "empty"),
        "empty image": ("empty.png", 1, "empty"),
        "text video": ("text.mp4", 1, "not a readable video"),
        "text image": ("text.png", 1, "not a readable image"),
        "cut to its head": ("head.mp4", 1, "head.mp4"),
        "audio only": ("audio.mp4", 1, "no video stream"),
    }


@contextlib.contextmanager
def av_audio_only(path: Path):
    import av

    with av.open(str(path), "w") as out:
        sound = out.add_stream("aac", rate=44100, layout="mono")
        for at in range(0, 44100, 1024):
            chunk = av.AudioFrame.from_ndarray(np.zeros((1, 1024), np.float32), "fltp", "mono")
            chunk.sample_rate, chunk.pts = 44100, at
            out.mux(sound.encode(chunk))
        out.mux(sound.encode(None))
    yield path


def test_broken_inputs_fail_in_one_line(cli, tmp_path, recipe, clip):
    cases = _media_cases(tmp_path, clip)
    before = {p.name: digest(p) for p in tmp_path.iterdir() if p.is_file()}
    for name, (src, code, expected) in cases.items():
        out = "o.png" if src.endswith(".png") else "o.mp4"
        proc = cli(src, "--ops", "r.json", "-o", out, "-q")
        assert proc.returncode == code, (name, proc.stderr)
        line = one_line(proc)
        assert expected in line and src in line, (name, line)
        assert not (tmp_path / out).exists() and leftovers(tmp_path) == [], name
    assert before == {p.name: digest(p) for p in tmp_path.iterdir() if p.is_file()}


def test_truncated_video_gives_what_it_has_or_one_line(cli, tmp_path, recipe, clip):
    """A file cut in half: either the frames before the cut (exit 0, a valid file) or a
    one-line refusal (exit 1) and nothing written."""
    data = clip.read_bytes()
    (tmp_path / "half.mp4").write_bytes(data[: len(data) // 2])
    proc = cli("half.mp4", "--ops", "r.json", "-o", "o.mp4", "-q")
    assert "Traceback" not in proc.stderr
    if proc.returncode == 0:
        import av

        with av.open(str(tmp_path / "o.mp4")) as got:
            assert sum(1 for _ in got.decode(video=0)) > 0
    else:
        assert proc.returncode == 1 and "half.mp4" in one_line(proc)
        assert not (tmp_path / "o.mp4").exists()
    assert leftovers(tmp_path) == []


def test_corrupt_packets_mid_stream_are_skipped_with_a_note(cli, tmp_path, recipe):
    write_clip(tmp_path / "bad.mp4", frames=20, codec="mpeg4", corrupt_at=8)
    proc = cli("bad.mp4", "--ops", "r.json", "-o", "o.mp4", "--progress", "off")
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    assert all(line.startswith("marblevideo: ") for line in proc.stderr.splitlines())
    assert (tmp_path / "o.mp4").stat().st_size > 0 and leftovers(tmp_path) == []


# ---------------------------------------------------------------------------- output faults


def _mount_tmpfs(folder: Path, options: str) -> None:
    folder.mkdir()
    proc = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)],
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({proc.stderr.strip() or 'not permitted'})")


@pytest.fixture
def mounted(tmp_path):
    mounts: list[Path] = []

    def mount(name: str, options: str) -> Path:
        folder = tmp_path / name
        _mount_tmpfs(folder, options)
        mounts.append(folder)
        return folder

    yield mount
    for folder in mounts:
        subprocess.run(["umount", str(folder)], capture_output=True)


def _noise_png(path: Path, side: int = 200) -> Path:
    cv2.imwrite(str(path), np.random.default_rng(0).integers(0, 256, (side, side, 3), np.uint8))
    return path


def test_disk_full_leaves_nothing(cli, tmp_path, recipe, mounted):
    small = mounted("small", "size=48k")
    _noise_png(tmp_path / "noise.png")
    before = digest(tmp_path / "noise.png")
    for out in ("full.png", "full.tif"):
        proc = cli("noise.png", "--ops", "r.json", "-o", small / out, "-q")
        assert proc.returncode == 1, proc.stderr
        line = one_line(proc)
        assert str(small / out) in line and "No space left on device" in line, line
        assert os.listdir(small) == []
    assert digest(tmp_path / "noise.png") == before


def test_disk_full_during_a_video_leaves_nothing(cli, tmp_path, mounted):
    small = mounted("small", "size=256k")
    (small / "filler").write_bytes(b"\0" * (256 - 4) * 1024)  # one 4 KB page left
    (tmp_path / "heavy.json").write_text(json.dumps(HEAVY))
    args = ["--size", "320x240", "--duration", "8", "-q"]
    proc = cli("--ops", "heavy.json", "-o", small / "v.mp4", *args)
    assert proc.returncode == 1, proc.stderr
    assert "No space left on device" in one_line(proc)
    assert os.listdir(small) == ["filler"]


def test_read_only_folder(cli, tmp_path, recipe, blank, mounted):
    ro = mounted("ro", "ro,size=64k")
    for out in ("o.png", "o.mp4"):
        timing = ["--duration", "0.2"] if out.endswith(".mp4") else []
        proc = cli("--ops", "blank.json", "-o", ro / out, "-q", *timing)
        assert proc.returncode == 1, proc.stderr
        assert "Read-only file system" in one_line(proc)
    assert os.listdir(ro) == []


def test_output_faults_never_harm_the_input(cli, tmp_path, recipe, clip):
    _noise_png(tmp_path / "in.png", 40)
    (tmp_path / "in.mp4").write_bytes(clip.read_bytes())
    (tmp_path / "taken.png").write_bytes(b"keep me")
    before = {p.name: digest(p) for p in tmp_path.iterdir() if p.is_file()}
    cases = [
        ("in.png", "in.png", 2, "same file as the input"),
        ("in.png", "./in.png", 2, "same file as the input"),
        ("in.mp4", "in.mp4", 2, "same file as the input"),
        ("in.png", "taken.png", 2, "use -y"),
        ("in.png", "missing/o.png", 2, "does not exist"),
        ("in.mp4", "missing/o.mp4", 2, "does not exist"),
        ("in.png", "o.xyz", 2, "unknown output extension"),
        ("in.mp4", "o", 2, "unknown output extension"),
        ("in.png", ".", 2, ""),
        ("in.mp4", "o.svg", 2, "cannot be vectorized"),
    ]
    for src, dst, code, expected in cases:
        proc = cli(src, "--ops", "r.json", "-o", dst, "-y" if dst == "in.png" else "-q")
        assert proc.returncode == code, (src, dst, proc.stderr)
        assert expected in one_line(proc), (dst, proc.stderr)
    after = {p.name: digest(p) for p in tmp_path.iterdir() if p.is_file()}
    assert after == before and leftovers(tmp_path) == []


# ---------------------------------------------------------------------------- interrupts


HEAVY = {
    "canvas": [640, 480],
    "antialias": "grid4",
    "ops": [
        {"type": "drop", "center": [320, 240], "radius": 100, "color": "#aa3300"},
        {
            "type": "vortex",
            "center": [320, 240],
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 60, "v": 3000}]},
            "lambda": 80,
        },
    ],
}


def _interrupt(tmp_path: Path, args: list[str], sig: int) -> subprocess.CompletedProcess:
    """Start a long render, wait for its first progress line, send ``sig``."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "marblevideo", *args, "--progress", "json"],
        cwd=tmp_path,
        stderr=subprocess.PIPE,
        stdout=subprocess.DEVNULL,
        text=True,
        env=subprocess_env(),
    )
    first = proc.stderr.readline()
    assert first.startswith('{"frame"'), first
    assert leftovers(tmp_path), "the temporary output should exist while encoding"
    return interrupt(proc, sig, timeout=30)


@pytest.mark.slow
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupting_a_blank_sheet_video(tmp_path, sig, code):
    (tmp_path / "heavy.json").write_text(json.dumps(HEAVY))
    args = ["--ops", "heavy.json", "-o", "long.mp4", "--duration", "60"]
    proc = _interrupt(tmp_path, args, sig)
    assert proc.returncode == code
    assert one_line(proc) == "marblevideo: interrupted"
    assert sorted(os.listdir(tmp_path)) == ["heavy.json"]


@pytest.mark.slow
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupting_a_transcode(tmp_path, sig, code):
    write_clip(tmp_path / "in.mp4", size=(320, 240), frames=150, audio=True)
    heavy = {**HEAVY, "canvas": None}
    heavy.pop("canvas")
    (tmp_path / "heavy.json").write_text(json.dumps(heavy))
    before = digest(tmp_path / "in.mp4")
    args = ["in.mp4", "--ops", "heavy.json", "-o", "out.mkv", "--size", "640x480"]
    proc = _interrupt(tmp_path, args, sig)
    assert proc.returncode == code
    assert one_line(proc) == "marblevideo: interrupted"
    assert sorted(os.listdir(tmp_path)) == ["heavy.json", "in.mp4"]
    assert digest(tmp_path / "in.mp4") == before


# ---------------------------------------------------------------------------- OpenCL faults


def test_no_opencl_platform(cli, tmp_path, blank):
    """An ICD loader that finds no driver: one line saying how to get one, exit 1."""
    empty = tmp_path / "no-vendors"
    empty.mkdir()
    env_backup = dict(os.environ)
    try:
        os.environ["OCL_ICD_VENDORS"] = str(empty)
        os.environ.pop("PYOPENCL_CTX", None)
        render = cli("--ops", "blank.json", "-o", "o.png")
        devices = cli("devices")
    finally:
        os.environ.clear()
        os.environ.update(env_backup)
    if "Portable Computing Language" in devices.stdout:
        pytest.skip("pyopencl's bundled PoCL ignores OCL_ICD_VENDORS")
    assert render.returncode == 1
    line = one_line(render)
    assert "no OpenCL device" in line and "pocl" in line
    assert devices.returncode == 1 and "pocl" in devices.stdout
    assert sorted(os.listdir(tmp_path)) == ["blank.json", "no-vendors"]


def test_kernel_build_failure_is_one_line():
    """The real build path with a source that does not compile (the renderer's
    source attribute replaced on a fresh instance, nothing else)."""
    renderer = fresh_renderer()  # fresh: its source is replaced
    renderer.programs.source = "__kernel void marble(__global uint *dst) { this is not C; }\n"
    with pytest.raises(DeviceError, match="OpenCL build failed") as info:
        renderer.kernel_for(Structure(("drop",), "none", "clamp", False))
    assert "\n" not in str(info.value)


def test_a_failed_prebuild_is_reported_by_the_render():
    renderer = fresh_renderer()  # fresh: its source is replaced
    renderer.programs.source = "__kernel void marble(__global uint *dst) { this is not C; }\n"
    structure = Structure(("drop",), "none", "clamp", False)
    renderer.prebuild(structure)  # fails in its thread, silently
    with pytest.raises(DeviceError, match="OpenCL build failed") as info:
        renderer.kernel_for(structure)
    assert "\n" not in str(info.value)


def test_unknown_device_choice_is_a_usage_error(cli, tmp_path, blank):
    proc = cli("--ops", "blank.json", "-o", "o.png", "--device", "7:7")
    assert proc.returncode == 2 and "no OpenCL device matches" in one_line(proc)
    proc = cli("--ops", "blank.json", "-o", "o.png", "--device", "no-such-gpu")
    assert proc.returncode == 2 and "devices:" in one_line(proc)
    assert sorted(os.listdir(tmp_path)) == ["blank.json"]


def test_readme_documents_exit_codes_and_limits():
    readme = (ROOT / "README.md").read_text()
    for text in ("0 done", "1 runtime failure", "2 usage or recipe error", "130/143", "141"):
        assert text in readme
    assert "## Limits" in readme
    for value in (f"{MAX_PIXELS:,}", f"{MAX_SIDE:,}", "1e30", "32 levels", "604,800 s"):
        assert value in readme, value


# ---------------------------------------------------------------------------- the command line

#: (the arguments, the one line): numbers that passed the options' checks and
#: overflowed later, and messages that misled (issue 54); run in this process.
REFUSED = [
    (["-o", "m.mp4", "--duration", "1e308"],
     "--duration: 1e+308 s is over the limit of 604800 s (MAX_SECONDS)"),
    (["-o", "m.mp4", "--fps", "1e308", "--duration", "1"],
     "--fps: 1e+308 fps is over the limit of 1000 fps (MAX_FPS)"),
    (["-o", "o.png", "--time", "-1"], "--time: must be >= 0 seconds, got -1"),
    (["-o", "o.png", "--time", "1e308"],
     "--time: 1e+308 s is over the limit of 604800 s (MAX_SECONDS)"),
    (["-o", "adir"], "adir: output is a folder; give a file name"),
    (["-o", "o.png", "--size", "-1x10"], "--size: expected WxH such as 1280x720, got '-1x10'"),
    (["-o", "o.png", "--ops", "binary.json"],
     "cannot read recipe binary.json: not UTF-8 text (a recipe is JSON text; byte 0x96 at "
     "offset 3 is not UTF-8)"),
    (["-o", "o.png", "--ops", "samples/swirl.json"],
     "cannot read recipe samples/swirl.json: No such file or directory; a preset has that "
     "name: --ops swirl (`marblevideo presets` lists them)"),
    (["-o", "m.mp4", "--ops", "long.json"],
     "long.json: the animation lasts 1e+30 s, over the limit of 604800 s (MAX_SECONDS); "
     "give --duration"),
]  # fmt: skip


@pytest.mark.parametrize("args, says", REFUSED, ids=[" ".join(a) for a, _ in REFUSED])
def test_options_are_refused_in_one_line_before_any_work(tmp_path, monkeypatch, blank, args, says):
    """Exit 2, one line, nothing written; never a traceback (an OverflowError
    from --duration 1e308 or from PyAV's stream of --fps 1e308, before)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "adir").mkdir()
    (tmp_path / "binary.json").write_bytes(b'{"o\x96' + bytes(range(256)) * 64)
    ops = [{"type": "drop", "center": [32, 24], "radius": 9, "color": "#2255aa", "start": 0,
            "end": 1e30}]  # fmt: skip
    (tmp_path / "long.json").write_text(json.dumps({**CANVAS, "ops": ops}))
    before = files(tmp_path)
    recipe = [] if "--ops" in args else ["--ops", "blank.json"]
    proc = run_main(*recipe, *args)
    assert proc.returncode == 2 and one_line(proc) == f"marblevideo: {says}"
    assert files(tmp_path) == before and not list((tmp_path / "adir").iterdir())


def test_an_option_value_may_start_with_a_dash():
    """argparse would take ``-5,0,10,10`` for an option (and say --view has no value);
    an option after one that takes a value is still an option."""
    args = _render_parser().parse_args(["--ops", "r.json", "-o", "-", "--view", "-5,0,10,10"])
    assert args.view == "-5,0,10,10" and args.output == "-"
    with pytest.raises(UsageError, match="argument --size: expected one argument"):
        _render_parser().parse_args(["--ops", "r.json", "-o", "o.png", "--size", "-q"])


def test_a_closed_standard_output_ends_quietly_with_141(tmp_path):
    """``marblevideo presets --paths | head`` with the reader gone before the first
    write: exit 141 (128 + SIGPIPE), nothing on stderr (a BrokenPipeError traceback
    about once in 20 runs, before)."""
    read, write = os.pipe()
    os.close(read)
    try:
        cmd = [sys.executable, "-m", "marblevideo", "presets", "--paths"]
        proc = subprocess.run(cmd, stdout=write, stderr=subprocess.PIPE, text=True,
                              env=subprocess_env(), timeout=60)  # fmt: skip
    finally:
        os.close(write)
    assert (proc.returncode, proc.stderr) == (141, "")
