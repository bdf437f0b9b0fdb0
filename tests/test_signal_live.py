"""Audio signals in live sessions: a file source's own audio is heard at each
shown frame's time in the file; a source with no audio is refused at the start
(one line, exit 2) unless --soundtrack gives one."""

from __future__ import annotations

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
    write_video_with_sound,
)

from marblevideo.live.session import LiveSession
from marblevideo.live.sources import MediaSource
from marblevideo.recipe import load_recipe
from marblevideo.signals import AudioSignals, analyse
from marblevideo.signals.live import LazyAudio, live_audio

pytestmark = pytest.mark.tier("fast")


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    folder = tmp_path_factory.mktemp("live")
    return write_video_with_sound(
        folder / "beat.mkv", beat_samples(2.0), BEAT_RATE, frames=50, size=(128, 72)
    )


def test_a_file_source_is_heard_at_each_frames_own_time(clip, renderer):
    source = MediaSource(str(clip))
    recipe_audio, by_frame = live_audio(load_recipe(PULSE), source)
    assert by_frame and isinstance(recipe_audio, LazyAudio)
    session = LiveSession(
        PULSE, source, renderer=renderer, quiet=True, audio=recipe_audio, audio_by_frame=True
    )
    try:
        signals = AudioSignals(analyse(clip, own=True))
        frame = np.zeros((72, 128, 4), np.uint8)
        for media_t in (0.6, 0.94, 1.06):  # the animation clock has not started: t ~ 0
            session.media_t = media_t
            out = session.show(frame, 0.0)
            want = expected_radius(signals, media_t)
            assert coral_radius(out, 0.1) == pytest.approx(want, abs=8), media_t
        assert expected_radius(signals, 1.06) - expected_radius(signals, 0.94) > 25
    finally:
        session.close()


def test_a_live_recording_breathes_with_its_source(cli, tmp_path, clip):
    out = tmp_path / "rec.mkv"
    proc = cli("live", clip, "--ops", PULSE, "--duration", 2.5, "-o", out, "--quiet")
    assert proc.returncode == 0, proc.stderr
    with av.open(str(out)) as container:
        radii = [coral_radius(f.to_ndarray(format="rgb24"), 0.1) for f in container.decode(video=0)]
    assert len(radii) >= 10
    assert max(radii) > 100 and min(radii) < 90


def test_a_source_with_no_audio_is_refused_unless_a_soundtrack_is_given(cli, tmp_path):
    proc = cli("live", "test", "--ops", PULSE, "--duration", 1, "-o", tmp_path / "a.mkv")
    assert proc.returncode == 2
    assert one_line(proc) == (
        f"marblevideo: {PULSE}: ops[9].radius: follows audio.low, but the source test pattern "
        "has no audio to follow; give one with --soundtrack FILE"
    )
    assert not (tmp_path / "a.mkv").exists()
    proc = cli("live", "test", "--ops", PULSE, "--duration", 1, "--soundtrack", "missing.wav")
    assert proc.returncode == 2 and "--soundtrack missing.wav: no such file" in one_line(proc)
