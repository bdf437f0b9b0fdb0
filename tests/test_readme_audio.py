"""The README's audio examples hold: its still lands on a swell of the beat
(the breathing drop near its widest, wider by far than at the kick's onset),
and its video over the bundled clip follows the beat (the drop's size rises and
falls with the kicks of samples/pulse.opus)."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys

import av
import cv2
import numpy as np
import pytest
from helpers import ROOT, subprocess_env
from sound import coral_radius, expected_radius

from marblevideo.signals.audio import analyse
from marblevideo.signals.values import AudioSignals

pytestmark = pytest.mark.tier("integration")

SCALE = 0.25  # renders at 320x180 of pulse.json's 1280x720 canvas


def readme_command(marker: str) -> list[str]:
    """The README's ```sh command that writes ``marker`` (comment dropped)."""
    text = (ROOT / "README.md").read_text()
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        for line in block.splitlines():
            if marker in line:
                return shlex.split(line, comments=True)
    raise AssertionError(f"no README command writes {marker}")


def run(words: list[str], cwd) -> subprocess.CompletedProcess:
    argv = [sys.executable, "-m", "marblevideo", *words[1:], "--size", "320x180"]
    proc = subprocess.run(argv, cwd=cwd, env=subprocess_env(), capture_output=True, timeout=300)
    assert proc.returncode == 0, proc.stderr.decode(errors="replace")
    return proc


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "samples").symlink_to(ROOT / "samples")
    return tmp_path


def test_the_readme_still_lands_on_a_swell(folder):
    words = readme_command("-o beat.png")
    at = float(words[words.index("--time") + 1])
    run(words, folder)
    swell = coral_radius(
        cv2.cvtColor(cv2.imread(str(folder / "beat.png")), cv2.COLOR_BGR2RGB), SCALE
    )
    onset = words.copy()
    onset[onset.index("--time") + 1] = f"{np.floor(at * 2) / 2:g}"  # the kick before it
    onset[onset.index("-o") + 1] = "onset.png"
    run(onset, folder)
    low = coral_radius(
        cv2.cvtColor(cv2.imread(str(folder / "onset.png")), cv2.COLOR_BGR2RGB), SCALE
    )
    assert swell > 105 and swell - low > 40, (swell, low)
    signals = AudioSignals(analyse(ROOT / "samples" / "pulse.opus", own=False))
    assert swell == pytest.approx(expected_radius(signals, at), abs=3)


def test_the_readme_clip_over_the_beat_pulses(folder):
    words = readme_command("-o coffee-pulse.mp4") + ["--end", "2.0"]
    run(words, folder)
    with av.open(str(folder / "coffee-pulse.mp4")) as container:
        radii = {
            round(float(f.time), 2): coral_radius(f.to_ndarray(format="rgb24"), SCALE)
            for f in container.decode(video=0)
        }
    signals = AudioSignals(analyse(ROOT / "samples" / "pulse.opus", own=False))
    expected = [expected_radius(signals, t) for t in radii]
    # the photo has coral-like pixels of its own: the measure follows the beat, offset
    assert np.corrcoef(list(radii.values()), expected)[0, 1] > 0.95, (radii, expected)
    assert max(radii.values()) - min(radii.values()) > 40, radii
