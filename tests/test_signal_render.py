"""File renders that follow the sound: samples/pulse.json over a generated beat,
--soundtrack (the output's audio, a music video on a blank sheet), stills at
--time, split renders, and the refusals (one line, exit 2, nothing written)."""

from __future__ import annotations

import json
from fractions import Fraction

import av
import numpy as np
import pytest
from helpers import one_line
from sound import (
    BEAT_RATE,
    PULSE,
    beat_samples,
    coral_radius,
    expected_radius,
    pcm16,
    write_video_with_sound,
    write_wav,
)

from marblevideo.jobs.pipeline import iter_frames
from marblevideo.marbler import Marbler
from marblevideo.recipe import load_recipe
from marblevideo.scale.segmented import render_split
from marblevideo.signals import AudioSignals, analyse
from marblevideo.signals.follow import follow

pytestmark = pytest.mark.tier("fast")


@pytest.fixture(scope="module")
def beat_clip(tmp_path_factory):
    """2 s of 64x36 frames at 25 fps with the beat (kicks at 0, 0.5, 1, 1.5 s)."""
    folder = tmp_path_factory.mktemp("beat")
    return write_video_with_sound(
        folder / "beat.mkv", beat_samples(2.0), BEAT_RATE, frames=50, size=(64, 36)
    )


def test_pulse_drops_breathe_with_the_beat(renderer, beat_clip):
    recipe = follow(load_recipe(PULSE), beat_clip)
    signals = AudioSignals(analyse(beat_clip, own=True))
    marbler = Marbler(recipe, renderer)
    radii = {}
    for t, frame in iter_frames(beat_clip, marbler.transform((640, 360))):
        radii[round(t, 2)] = r = coral_radius(frame, 0.5)
        assert r == pytest.approx(expected_radius(signals, t), abs=2.0), t
    for kick in (0.0, 0.5, 1.0, 1.5):
        after = radii[min(t for t in radii if t >= kick + 0.05)]  # a window of kick
        before_next = radii[max(t for t in radii if t < kick + 0.5)]
        assert after > 105 and before_next < 90 and after - before_next > 25, (kick, radii)
    assert radii[0.0] == pytest.approx(40, abs=2)  # nothing heard before t = 0


def test_a_stream_starting_late_is_heard_late(renderer, tmp_path):
    clip = write_video_with_sound(
        tmp_path / "late.mkv",
        beat_samples(1.0),
        BEAT_RATE,
        audio_start=Fraction(1, 2),
        frames=40,
        size=(64, 36),
    )
    marbler = Marbler(follow(load_recipe(PULSE), clip), renderer)
    radii = {
        round(t, 2): coral_radius(f, 0.25)
        for t, f in iter_frames(clip, marbler.transform((320, 180)))
    }
    assert all(r == pytest.approx(40, abs=4) for t, r in radii.items() if t < 0.5)
    assert radii[0.56] > 105  # the first kick, at 0.5 s on the video's clock


def test_segments_hear_the_whole_file(renderer, beat_clip, tmp_path):
    """A split render marbles each segment's frames at the whole input's times and
    envelope: its frames equal the single render's (lossless x264)."""
    options = dict(crf=0, preset="ultrafast", size=(128, 72), quiet=True, progress="off")
    render_split(beat_clip, PULSE, tmp_path / "split.mp4", cluster="serial", segments=2, **options)
    from marblevideo.api import render_video

    render_video(beat_clip, PULSE, tmp_path / "whole.mp4", renderer=renderer, **options)
    with av.open(str(tmp_path / "split.mp4")) as a, av.open(str(tmp_path / "whole.mp4")) as b:
        split = [f.to_ndarray(format="rgb24") for f in a.decode(video=0)]
        whole = [f.to_ndarray(format="rgb24") for f in b.decode(video=0)]
    assert len(split) == len(whole) == 50
    assert all(np.array_equal(x, y) for x, y in zip(split, whole, strict=True))
    assert not np.array_equal(whole[1], whole[20])  # it moved


def test_a_music_video_on_a_blank_sheet(cli, tmp_path):
    sound = write_wav(tmp_path / "beat.wav", beat_samples(1.5), BEAT_RATE)
    out = tmp_path / "music.mkv"
    args = [
        "--ops",
        PULSE,
        "--soundtrack",
        sound,
        "--duration",
        1,
        "--fps",
        10,
        "--size",
        "320x180",
    ]
    proc = cli(*args, "--codec", "ffv1", "-o", out)
    assert proc.returncode == 0, proc.stderr
    with av.open(str(out)) as container:
        frames = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
        container.seek(0)
        heard = np.concatenate([f.to_ndarray().reshape(-1) for f in container.decode(audio=0)])
    assert len(frames) == 10
    # the soundtrack's samples, copied, from its first at t = 0 to the video's end
    want = beat_samples(1.5).reshape(-1)
    assert 1.0 * BEAT_RATE <= len(heard) <= 1.2 * BEAT_RATE
    assert np.array_equal(heard, want[: len(heard)])
    assert coral_radius(frames[1], 0.25) > 105 and coral_radius(frames[4], 0.25) < 90


def test_stills_at_a_time_follow_the_soundtrack(cli, tmp_path):
    import cv2

    sound = write_wav(tmp_path / "beat.wav", beat_samples(1.0), BEAT_RATE)
    radii = []
    for t in (0.04, 0.44):
        out = tmp_path / f"at{t}.png"
        proc = cli(
            "--ops", PULSE, "--soundtrack", sound, "--time", t, "--size", "320x180", "-o", out
        )
        assert proc.returncode == 0, proc.stderr
        radii.append(coral_radius(cv2.cvtColor(cv2.imread(str(out)), cv2.COLOR_BGR2RGB), 0.25))
    assert radii[0] > 105 and radii[1] < 90


OSC = json.dumps(
    {
        "canvas": [64, 36],
        "ops": [
            {
                "type": "vortex",
                "center": [32, 18],
                "lambda": 9,
                "alpha": {"signal": "osc:/swirl", "range": [0, 90]},
            }
        ],
    }
)
MIDI_TOP = json.dumps(
    {
        "canvas": [64, 36],
        "ops": [
            {"type": "drop", "center": [3, 3], "radius": 2, "color": "red"},
            {
                "type": "drop",
                "center": [32, 18],
                "color": "red",
                "radius": {"signal": "midi:note:2:60", "range": [1, 9]},
            },
        ],
    }
)


@pytest.mark.parametrize(
    ("recipe", "inputs", "extra", "expected"),
    [
        (
            None,
            [],
            [],
            "pulse.json: ops[9].radius: follows audio.low, but there is no audio to follow (a "
            "blank sheet has no audio); give one with --soundtrack FILE",
        ),
        (None, ["image"], [], "ops[9].radius: follows audio.low, but there is no audio to follow"),
        (None, ["silent"], [], "silent.mp4 has no audio stream); give one with --soundtrack FILE"),
        (None, [], ["--soundtrack", "missing.wav"], "--soundtrack missing.wav: no such file"),
        (None, [], ["--soundtrack", "pulse.json"], "no audio stream to read"),
        (
            OSC,
            ["beat"],
            [],
            "osc.json: ops[0].alpha: follows the controller osc:/swirl, which only a live session "
            "hears (marblevideo live); its --automation FILE records what the controllers did as "
            "keyframes that a file render takes",
        ),
        (
            MIDI_TOP,
            [],
            ["--time", "1"],
            "osc.json: ops[1].radius: follows the controller midi:note:2:60",
        ),
        (
            None,
            ["beat"],
            ["--cluster", "ray", "--soundtrack", "beat.wav"],
            "--soundtrack: not with --cluster",
        ),
    ],
)
def test_refusals_are_one_line_exit_2_and_write_nothing(
    cli, tmp_path, beat_clip, recipe, inputs, extra, expected
):
    import shutil

    import cv2
    from clips import write_clip

    ops = PULSE
    if recipe is not None:
        ops = tmp_path / "osc.json"
        ops.write_text(recipe)
    shutil.copy(PULSE, tmp_path / "pulse.json")
    write_wav(tmp_path / "beat.wav", beat_samples(0.2), BEAT_RATE)
    paths = {"beat": beat_clip}
    if "image" in inputs:
        cv2.imwrite(str(tmp_path / "photo.png"), np.zeros((36, 64, 3), np.uint8))
        paths["image"] = tmp_path / "photo.png"
    if "silent" in inputs:
        paths["silent"] = write_clip(tmp_path / "silent.mp4", frames=3, audio=False)
    out = tmp_path / ("out.png" if "--time" in extra else "out.mp4")
    proc = cli(*[paths[i] for i in inputs], "--ops", ops, *extra, "-o", out)
    assert proc.returncode == 2, proc.stderr
    assert expected in one_line(proc)
    assert not out.exists()


def test_a_batch_refuses_an_input_with_nothing_to_follow_before_any_work(cli, tmp_path, beat_clip):
    import shutil

    import cv2

    shutil.copy(beat_clip, tmp_path / "a.mkv")
    cv2.imwrite(str(tmp_path / "b.png"), np.zeros((36, 64, 3), np.uint8))
    proc = cli("batch", "*.mkv", "*.png", "--ops", PULSE, "-o", "{stem}-out.png", "--time", 0.1)
    assert proc.returncode == 2
    assert (
        "ops[9].radius: follows audio.low, but there is no audio to follow (b.png is an image"
        in (one_line(proc))
    )
    assert not list(tmp_path.glob("*-out.png"))


def test_the_soundtrack_replaces_the_inputs_audio_on_the_renders_clock(cli, tmp_path, beat_clip):
    """From --start 0.5: the output's audio is the soundtrack's from the first frame
    kept on, placed where it plays against the frames (whole packets, copied)."""
    from sound import tone

    sound = pcm16([tone(440, 2.0, BEAT_RATE, 0.5)])
    write_wav(tmp_path / "tone.wav", sound, BEAT_RATE)
    out = tmp_path / "out.mkv"
    proc = cli(beat_clip, "--ops", PULSE, "--soundtrack", "tone.wav", "--start", 0.5, "-o", out)
    assert proc.returncode == 0, proc.stderr
    with av.open(str(out)) as container:
        assert len(container.streams.audio) == 1
        frames = list(container.decode(audio=0))
    first = float(frames[0].pts * frames[0].time_base)
    heard = np.concatenate([f.to_ndarray().reshape(-1) for f in frames])
    # the output starts at the first frame kept (0.52 s at 25 fps), its audio with it
    at = round((first + 0.52) * BEAT_RATE)  # the soundtrack's sample at the output's first audio
    assert 0 <= first < 0.2
    whole = sound.reshape(-1)
    # Matroska keeps milliseconds: the sample is within one of them
    near = [k for k in range(at - 23, at + 24) if np.array_equal(heard, whole[k : k + len(heard)])]
    assert len(near) == 1, (at, first)
    assert 1.3 * BEAT_RATE <= len(heard) <= 1.6 * BEAT_RATE  # up to the video's end (2 s)
