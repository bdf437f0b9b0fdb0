"""The media users bring and want, end to end through the real CLI and API:
GIF, APNG and animated WebP; image sequences in and out; frame grabs; stills
animated to video; frame-rate conversion; pipes; URLs; --fit; options that do
not apply. Frames are checked against the NumPy reference or against the
lossless route of the same run; timing against the input.
"""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from clips import probe, write_clip
from helpers import ROOT, files, one_line
from PIL import Image
from tolerances import KERNEL_LEVELS, KERNEL_SHARE

from benchmarks.webfolder import serve_folder
from marblevideo import api
from marblevideo.errors import UsageError
from marblevideo.jobs.pipeline import iter_frames
from marblevideo.recipe import load_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("integration")

#: An animated recipe: a drop appears while a comb and a vortex grow.
RECIPE = {
    "marblevideo": 1,
    "canvas": [96, 64],
    "antialias": "rgss",
    "edges": "mirror",
    "ops": [
        {
            "type": "drop",
            "center": [48, 32],
            "radius": 12,
            "color": "tomato",
            "start": 0.2,
            "end": 0.6,
        },  # fmt: skip
        {
            "type": "comb",
            "point": [0, 0],
            "angle": 90,
            "spacing": 24,
            "lambda": 4,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 1, "v": 14}]},
        },  # fmt: skip
        {
            "type": "vortex",
            "center": [48, 32],
            "lambda": 20,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 1, "v": 90}]},
        },  # fmt: skip
    ],
}
#: A recipe that moves nothing (so input pixels can be traced).
IDENTITY = {
    "marblevideo": 1,
    "canvas": [96, 64],
    "background": "#204080",
    "ops": [{"type": "wave", "phase": 0, "angle": 0, "amplitude": 0, "wavelength": 30}],
}


@pytest.fixture
def clip(tmp_path):
    """30 frames at 30 fps (1 s), 96x64, with audio; frame i has green 8 i."""
    return write_clip(tmp_path / "in.mp4", size=(96, 64), frames=30, fps=30, audio=True)


@pytest.fixture
def recipe(tmp_path):
    (tmp_path / "r.json").write_text(json.dumps(RECIPE))
    (tmp_path / "same.json").write_text(json.dumps(IDENTITY))
    return tmp_path / "r.json"


def _rgb(path) -> np.ndarray:
    return cv2.imread(str(path), cv2.IMREAD_COLOR)[:, :, ::-1]


def _sequence(folder) -> list[np.ndarray]:
    return [_rgb(p) for p in sorted(folder.iterdir())]


def _animation(path) -> tuple[list[np.ndarray], list[int], int]:
    """(RGB frames, frame durations in ms, loop count) of a GIF, APNG or WebP."""
    with Image.open(path) as im:
        frames, durations = [], []
        for i in range(im.n_frames):
            im.seek(i)
            frames.append(np.asarray(im.convert("RGB")))
            durations.append(im.info["duration"])
        return frames, durations, im.info.get("loop")


def _within_kernel(ours: np.ndarray, ref: np.ndarray) -> bool:
    diff = np.abs(ours.astype(np.int16) - ref[..., :3].astype(np.int16)).max(axis=2)
    return (diff <= KERNEL_LEVELS).mean() >= KERNEL_SHARE


def _clock(times: list[float]) -> np.ndarray:
    """Video times from the first frame (Matroska starts the clock where the
    AAC priming's negative timestamps end: 23 ms here)."""
    return np.asarray(times) - times[0]


def _green(frame: np.ndarray) -> int:
    """The source frame index a traced frame shows (its green level is 8 i)."""
    return round(float(np.median(frame[20:, 20:, 1])) / 8)


# ----------------------------------------------------------------- animated stills


def test_gif_apng_webp_hold_every_frame_and_its_delay(cli, tmp_path, clip, recipe):
    (tmp_path / "seq").mkdir()
    assert cli("in.mp4", "--ops", "r.json", "-o", "seq/f_%03d.png", "-q").returncode == 0
    lossless = _sequence(tmp_path / "seq")
    assert len(lossless) == 30
    for name, extra in (("a.gif", []), ("a.apng", []), ("a.webp", ["--format", "webp"])):
        proc = cli("in.mp4", "--ops", "r.json", "-o", name, "-q", *extra)
        assert proc.returncode == 0, proc.stderr
        frames, durations, loop = _animation(tmp_path / name)
        assert len(frames) == 30 and loop == 0, name  # every frame, looping forever
        # 1/30 s each: GIF counts centiseconds (3 or 4, 1 s in all), the others ms
        assert abs(sum(durations) - 1000) <= 10 and max(durations) <= 40, (name, durations)
        error = [np.abs(a.astype(int) - b).mean() for a, b in zip(frames, lossless, strict=True)]
        if name == "a.apng":
            assert max(error) == 0  # lossless: the PNG sequence, exactly
        else:
            assert max(error) < 6, (name, error)  # a palette / lossy WebP, close
    with Image.open(tmp_path / "a.gif") as gif:
        assert len(gif.getpalette()) // 3 <= 256


def test_gif_palette_is_the_clips(cli, tmp_path, recipe):
    """One palette from all frames: a colour only the last frames show is in it."""
    write_clip(tmp_path / "in.mp4", size=(64, 48), frames=30, fps=30, audio=False)
    proc = cli("in.mp4", "--ops", "same.json", "-o", "a.gif", "-q")
    assert proc.returncode == 0, proc.stderr
    frames, _, _ = _animation(tmp_path / "a.gif")
    for i in (0, 29):  # green 0 and 232: both well reproduced
        assert abs(_green(frames[i]) - i) <= 0, i


# ----------------------------------------------------------------- sequences


def test_sequence_out_and_back_in(cli, tmp_path, clip, recipe):
    (tmp_path / "seq").mkdir()
    proc = cli("in.mp4", "--ops", "same.json", "-o", "seq/f_%04d.png", "-q")
    assert proc.returncode == 0, proc.stderr
    assert files(tmp_path / "seq") == [f"f_{i:04d}.png" for i in range(1, 31)]
    assert [_green(f) for f in _sequence(tmp_path / "seq")] == list(range(30))
    # existing frames are kept unless -y
    again = cli("in.mp4", "--ops", "same.json", "-o", "seq/f_%04d.png", "-q")
    assert again.returncode == 2 and "-y" in one_line(again)
    # read back at 12 fps: a frame per file at i / 12 s
    proc = cli("seq/f_%04d.png", "--fps", "12", "--ops", "same.json", "-o", "b.mkv", "-q")
    assert proc.returncode == 0, proc.stderr
    back = probe(tmp_path / "b.mkv")
    assert len(back.frames) == 30
    assert np.allclose(_clock(back.times), np.arange(30) / 12, atol=1e-3)
    assert [_green(f) for f in back.frames] == list(range(30))


def test_sequence_input_matches_the_reference(tmp_path, recipe):
    folder = tmp_path / "shots"
    folder.mkdir()
    rng = np.random.default_rng(3)
    for i in range(5):
        cv2.imwrite(str(folder / f"shot-{i + 7}.png"), rng.integers(0, 256, (64, 96, 3), np.uint8))
    out = tmp_path / "o"
    out.mkdir()
    api.render_video(folder / "shot-%d.png", recipe, out / "m_%02d.png", fps=5, quiet=True)
    made = _sequence(out)
    spec_recipe = load_recipe(recipe)
    assert len(made) == 5  # numbered from the first file found (7), written from 1
    for i, ours in enumerate(made):
        image = cv2.imread(str(folder / f"shot-{i + 7}.png"))[:, :, ::-1]
        ref = reference_render(spec_recipe.at(i / 5, None), geometry((96, 64), (96, 64), (96, 64)),
                               image)  # fmt: skip
        assert _within_kernel(ours, ref), i


# ----------------------------------------------------------------- frame grabs and stills


def test_frame_grab_is_the_frame_shown_at_time(cli, tmp_path, clip, recipe):
    inputs = dict(iter_frames(clip))
    times = sorted(inputs)
    loaded = load_recipe(recipe)
    for when, expected in (
        (None, times[0]),
        (0.5, times[15]),
        (0.51, times[15]),
        (0.99, times[-1]),
    ):
        args = [] if when is None else ["--time", str(when)]
        proc = cli("in.mp4", "--ops", "r.json", "-o", "grab.png", "-y", "-q", *args)
        assert proc.returncode == 0, proc.stderr
        ref = reference_render(
            loaded.at(expected, None), geometry((96, 64), (96, 64), (96, 64)), inputs[expected]
        )
        assert _within_kernel(_rgb(tmp_path / "grab.png"), ref), when
    late = cli("in.mp4", "--ops", "r.json", "-o", "late.png", "--time", "9")
    assert late.returncode == 2 and "after the last frame" in one_line(late)


def test_still_animated_to_video(cli, tmp_path, recipe):
    rng = np.random.default_rng(5)
    cv2.imwrite(str(tmp_path / "photo.png"), rng.integers(0, 256, (64, 96, 3), np.uint8))
    proc = cli("photo.png", "--ops", "r.json", "-o", "a.mp4", "--fps", "12", "--duration", "2")
    assert proc.returncode == 0, proc.stderr
    video = probe(tmp_path / "a.mp4")
    assert len(video.frames) == 24 and np.allclose(video.times, np.arange(24) / 12, atol=1e-3)
    # default: the animation (1 s) plus one second at 30 fps
    assert cli("photo.png", "--ops", "r.json", "-o", "b.mp4", "-q").returncode == 0
    assert len(probe(tmp_path / "b.mp4").frames) == 60
    # frame k of a lossless sequence is the still rendered at k / fps, exactly
    (tmp_path / "seq").mkdir()
    args = ["--fps", "4", "--duration", "1", "-q"]
    assert cli("photo.png", "--ops", "r.json", "-o", "seq/%d.png", *args).returncode == 0
    for k in range(4):
        proc = cli("photo.png", "--ops", "r.json", "-o", f"s{k}.png", "--time", str(k / 4), "-q")
        assert proc.returncode == 0, proc.stderr
        assert np.array_equal(_rgb(tmp_path / f"seq/{k + 1}.png"), _rgb(tmp_path / f"s{k}.png"))


# ----------------------------------------------------------------- frame rate


@pytest.mark.parametrize(
    "fps, expected",
    [
        # ffmpeg's fps filter (round=near): a slot shows the latest frame rounded into it
        (10, [1] + [min(3 * n + 1, 29) for n in range(1, 10)]),
        (60, [i // 2 for i in range(60)]),  # each frame twice
        (30, list(range(30))),
    ],
)
def test_fps_converts_a_video(cli, tmp_path, clip, recipe, fps, expected):
    proc = cli("in.mp4", "--ops", "same.json", "-o", "o.mkv", "--fps", str(fps), "--crf", "0")
    assert proc.returncode == 0, proc.stderr
    out = probe(tmp_path / "o.mkv")
    assert [_green(f) for f in out.frames] == expected
    assert np.allclose(_clock(out.times), np.arange(len(expected)) / fps, atol=1e-3)
    assert out.audio_codec is not None and out.audio_times[-1] > 0.9  # audio kept


def test_fps_moves_the_animation_at_the_new_rate(tmp_path, clip, recipe):
    """A repeated input frame is marbled at its own slot's time, not its source's."""
    out = tmp_path / "seq"
    out.mkdir()
    api.render_video(clip, recipe, out / "%02d.png", fps=60, quiet=True)
    frames = _sequence(out)
    assert len(frames) == 60
    loaded = load_recipe(recipe)
    inputs = dict(iter_frames(clip))
    times = sorted(inputs)
    for k in (21, 22, 41):
        ref = reference_render(
            loaded.at(k / 60, None), geometry((96, 64), (96, 64), (96, 64)), inputs[times[k // 2]]
        )
        assert _within_kernel(frames[k], ref), k
    assert not np.array_equal(frames[21], frames[20])  # same input frame, later time


# ----------------------------------------------------------------- pipes and URLs


def test_pipe_through_matroska(cli, tmp_path, clip, recipe):
    """``marblevideo - ... -o - --format matroska``: stdin to stdout, as ffmpeg chains.
    FFV1 (lossless) for a frame-exact comparison: libx264 is not bit-reproducible
    from run to run on frames this small, even on one thread."""
    args = ["-", "--ops", "r.json", "-o", "-", "--format", "matroska", "--codec", "ffv1", "-q"]
    proc = cli(*args, input=clip.read_bytes())
    assert proc.returncode == 0, proc.stderr.decode()
    assert proc.stderr == b""  # -q: nothing on stderr; the video alone on stdout
    (tmp_path / "piped.mkv").write_bytes(proc.stdout)
    piped = probe(tmp_path / "piped.mkv")
    source = probe(clip)
    assert len(piped.frames) == 30
    assert np.allclose(_clock(piped.times), source.times, atol=1e-3)
    assert piped.audio_packets == source.audio_packets  # audio copied
    # the same frames as the file route
    api.render_video(clip, recipe, tmp_path / "file.mkv", codec="ffv1", quiet=True)
    for a, b in zip(piped.frames, probe(tmp_path / "file.mkv").frames, strict=True):
        assert np.array_equal(a, b)


def test_a_sequence_with_no_files(cli, tmp_path, recipe):
    proc = cli("seq/f_%03d.png", "-o", "o.mp4", "--ops", "r.json")
    assert proc.returncode == 1 and "no files of this image sequence" in one_line(proc)
    assert "o.mp4" not in files(tmp_path)


def test_pipe_of_an_mp4_indexed_last(cli, recipe):
    """An MP4 whose index (moov) follows its data cannot be read from a pipe once
    the data outgrows FFmpeg's probe buffer: one line saying why, exit 1."""
    data = (ROOT / "samples" / "coffee.mp4").read_bytes()
    assert data.index(b"moov") > data.index(b"mdat") > 0 and len(data) > 65536
    proc = cli("-", "--ops", "r.json", "-o", "-", "--format", "nut", "-q", input=data)
    assert proc.returncode == 1
    (line,) = proc.stderr.decode().splitlines()
    assert line.startswith("marblevideo: -: cannot read") and "+faststart" in line


@pytest.mark.parametrize("fmt", ["nut", "mpegts", "y4m", "mp4"])
def test_pipe_formats(cli, tmp_path, clip, recipe, fmt):
    proc = cli("-", "--ops", "r.json", "-o", "-", "--format", fmt, input=clip.read_bytes())
    assert proc.returncode == 0, proc.stderr.decode()
    assert proc.stdout and b"marblevideo" not in proc.stdout
    out = tmp_path / f"o.{fmt}"
    out.write_bytes(proc.stdout)
    assert len(probe(out).frames) == 30


def test_pipe_stills(cli, tmp_path, recipe):
    rng = np.random.default_rng(9)
    image = rng.integers(0, 256, (64, 96, 3), np.uint8)
    data = cv2.imencode(".png", image)[1].tobytes()
    proc = cli("-", "--ops", "r.json", "-o", "-", "--format", "png", "--time", "1", input=data)
    assert proc.returncode == 0, proc.stderr.decode()
    ours = cv2.imdecode(np.frombuffer(proc.stdout, np.uint8), cv2.IMREAD_COLOR)[:, :, ::-1]
    ref = reference_render(load_recipe(recipe).at(1.0, None),
                           geometry((96, 64), (96, 64), (96, 64)), image[:, :, ::-1])  # fmt: skip
    assert _within_kernel(ours, ref)
    # a still on stdin animated to a video on stdout
    proc = cli(
        "-", "--ops", "r.json", "-o", "-", "--format", "nut", "--duration", "0.5", input=data
    )
    assert proc.returncode == 0, proc.stderr.decode()
    (tmp_path / "o.nut").write_bytes(proc.stdout)
    assert len(probe(tmp_path / "o.nut").frames) == 15


def test_url_input(cli, tmp_path, clip, recipe):
    with serve_folder(tmp_path) as base:
        proc = cli(f"{base}/in.mp4", "--ops", "r.json", "-o", "url.mkv", "--codec", "ffv1")
        assert proc.returncode == 0, proc.stderr
        grab = cli(f"{base}/in.mp4", "--ops", "r.json", "-o", "url.png", "--time", "0.5")
        assert grab.returncode == 0, grab.stderr
        missing = cli(f"{base}/nope.mp4", "--ops", "r.json", "-o", "nope.mkv", "-q")
    assert missing.returncode == 1 and "404" in one_line(missing)
    api.render_video(clip, recipe, tmp_path / "file.mkv", codec="ffv1", quiet=True)
    for a, b in zip(probe(tmp_path / "url.mkv").frames, probe(tmp_path / "file.mkv").frames,
                    strict=True):  # fmt: skip
        assert np.array_equal(a, b)
    assert "nope.mkv" not in files(tmp_path)


# ----------------------------------------------------------------- --fit


def test_fit_crop_pad_stretch(cli, tmp_path, recipe):
    wide = np.zeros((32, 64, 3), np.uint8)
    wide[:, :, 0] = np.arange(64)[None, :] * 4  # a red ramp left to right
    wide[:, :, 1] = 200
    cv2.imwrite(str(tmp_path / "wide.png"), wide[:, :, ::-1])
    made = {}
    for fit in ("crop", "pad", "stretch"):
        proc = cli("wide.png", "--ops", "same.json", "--size", "32x32", "--fit", fit, "-o",
                   f"{fit}.png")  # fmt: skip
        assert proc.returncode == 0, proc.stderr
        made[fit] = _rgb(tmp_path / f"{fit}.png").astype(int)
        assert made[fit].shape == (32, 32, 3)
        assert "stretched" not in proc.stderr  # asked for: no notice
    unasked = cli("wide.png", "--ops", "same.json", "--size", "32x32", "-o", "default.png")
    assert "stretched" in unasked.stderr and "--fit" in unasked.stderr  # the default says so
    assert np.array_equal(_rgb(tmp_path / "default.png"), made["stretch"])
    # crop: the middle 32 columns, unscaled
    assert np.abs(made["crop"] - wide[:, 16:48]).max() <= 1
    # pad: the whole image scaled to 32x16 between bands of the background (#204080),
    # antialiased where they meet (rows 7, 8, 23 and 24)
    band = [0x20, 0x40, 0x80]
    assert (made["pad"][:7] == band).all() and (made["pad"][25:] == band).all()
    scaled = cv2.resize(wide, (32, 16), interpolation=cv2.INTER_AREA)
    assert np.abs(made["pad"][9:23, 1:-1] - scaled[1:-1, 1:-1]).max() <= 6
    # stretch: every column kept, squeezed in x
    squeezed = cv2.resize(wide, (32, 32), interpolation=cv2.INTER_AREA)
    assert np.abs(made["stretch"] - squeezed)[:, 1:-1].max() <= 6


def test_fit_applies_to_video(tmp_path, clip, recipe):
    api.render_video(clip, tmp_path / "same.json", tmp_path / "o.mkv", size=(64, 64), fit="pad",
                     crf=0, quiet=True)  # fmt: skip
    frame = probe(tmp_path / "o.mkv").frames[0].astype(int)
    assert frame.shape == (64, 64, 3)
    assert np.abs(frame[:6] - [0x20, 0x40, 0x80]).max() <= 3  # a band of the background
    assert frame[32, 32, 1] < 10  # frame 0: green 0 in the middle


# ----------------------------------------------------------------- options that do not apply


@pytest.mark.parametrize(
    "args, fault",
    [
        (["in.mp4", "-o", "o.png", "--duration", "2"], "--duration: applies to video outputs"),
        (["in.mp4", "-o", "o.png", "--fps", "5"], "--fps: applies to video outputs"),
        (["in.mp4", "-o", "o.gif", "--crf", "20"], "--crf: gif has no option 'crf'"),
        (["in.mp4", "-o", "o.png", "--crf", "20"], "--crf"),
        (["in.mp4", "-o", "-"], "-o -: name the stream's format with --format"),
        (["in.mp4", "-o", "o.mp4", "--format", "bogus"], "unknown format 'bogus'"),
        (["in.mp4", "-o", "o.mp4", "--fit", "squash"], "--fit"),
        (["in.mp4", "-o", "o.mp4", "--fps", "0"], "--fps"),
        (["in.mp4", "-o", "o.svg"], "cannot be vectorized"),
        (["-o", "o.png", "--fit", "crop"], "--fit"),
    ],
)
def test_options_that_do_not_apply(cli, tmp_path, clip, recipe, args, fault):
    before = files(tmp_path)
    proc = cli(*args, "--ops", "r.json")
    assert proc.returncode == 2, proc.stderr
    assert fault in one_line(proc)
    assert files(tmp_path) == before  # refused before any work: nothing written


# ------------------------------------------------- option values: one check, CLI and API alike


@pytest.mark.parametrize(
    "src, args, keywords, fault",
    [
        (None, ["--start", "1"], {"start": 1.0},
         "--start: a blank sheet has no timeline; use --duration"),
        ("img.png", ["--end", "1"], {"end": 1.0},
         "--end: img.png, a still has no timeline; use --duration"),
        ("in.mp4", ["--duration", "1", "--end", "2"], {"duration": 1.0, "end": 2.0},
         "--duration and --end: give one"),
        ("in.mp4", ["--fps", "0"], {"fps": 0.0}, "--fps: must be > 0, got 0"),
        (None, ["--duration", "-1"], {"duration": -1.0}, "--duration: must be > 0, got -1"),
        (None, ["--duration", "1e308"], {"duration": 1e308},
         "--duration: 1e+308 s is over the limit of 604800 s (MAX_SECONDS)"),
        ("in.mp4", ["--fps", "1e308"], {"fps": 1e308},
         "--fps: 1e+308 fps is over the limit of 1000 fps (MAX_FPS)"),
        ("in.mp4", ["--start", "1e308"], {"start": 1e308},
         "--start: 1e+308 s is over the limit of 604800 s (MAX_SECONDS)"),
    ],
)  # fmt: skip
def test_option_values_are_refused_alike_by_the_cli_and_the_api(
    cli, tmp_path, clip, recipe, src, args, keywords, fault
):
    """One check of the options' values against the input: the command line and
    render_video refuse in the same words, before any work."""
    cv2.imwrite(str(tmp_path / "img.png"), np.zeros((16, 16, 3), np.uint8))
    before = files(tmp_path)
    source = [] if src is None else [src]
    proc = cli(*source, "--ops", "r.json", "-o", "o.mp4", *args)
    assert proc.returncode == 2 and one_line(proc) == f"marblevideo: {fault}"
    with pytest.raises(UsageError) as err:
        api.render_video(
            None if src is None else tmp_path / src, recipe, tmp_path / "o.mp4", **keywords
        )  # fmt: skip
    assert str(err.value) == fault.replace("img.png", str(tmp_path / "img.png"))
    assert files(tmp_path) == before


def test_unknown_keywords_are_refused(tmp_path, clip, recipe):
    with pytest.raises(UsageError, match="render_video: unknown options bogus"):
        api.render_video(clip, recipe, tmp_path / "o.mp4", bogus=1)
