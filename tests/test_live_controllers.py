"""``marblevideo live --osc ... --automation FILE`` end to end: a real session
(a still photo looped, so any change comes from the controller), OSC over UDP
on loopback, the recording decoded by PyAV, and the take rendered again from
FILE by the OpenCL renderer over the same source."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import av
import numpy as np
import pytest
from helpers import ROOT
from live_helpers import LiveProcess
from pythonosc.udp_client import SimpleUDPClient

from marblevideo.marbler import Marbler
from marblevideo.media.decode import upright
from marblevideo.recipe import parse_recipe

pytestmark = pytest.mark.tier("fast")

PHOTO = ROOT / "samples" / "coffee.jpg"  # 600x400
RECIPE = {
    "marblevideo": 1,
    "antialias": "none",
    "edges": "mirror",
    "ops": [
        {
            "type": "vortex",
            "center": [300, 200],
            "alpha": {"signal": "osc:/swirl", "range": [0, 400], "initial": 0.1},
            "lambda": 80,
        }
    ],
}


def _photo() -> np.ndarray:
    with av.open(str(PHOTO)) as c:
        return upright(next(c.decode(video=0)))


def _recording(path):
    """[(t seconds, rgb frame)] of a recording."""
    with av.open(str(path)) as c:
        stream = c.streams.video[0]
        return [
            (float(f.pts * stream.time_base), f.to_ndarray(format="rgb24"))
            for f in c.decode(stream)
        ]


def test_a_take_driven_by_osc_renders_again_from_its_automation(tmp_path, renderer):
    recipe, take, auto = tmp_path / "r.json", tmp_path / "take.mkv", tmp_path / "take.json"
    recipe.write_text(json.dumps(RECIPE))
    live = LiveProcess(
        PHOTO, "--loop", "--ops", recipe, "--preview", "--port", "0", "--osc", "0",
        "--duration", "5", "-o", take, "--codec", "ffv1", "--pix-fmt", "bgr0",
        "--automation", auto, cwd=tmp_path,
    )  # fmt: skip
    try:
        line = live.proc.stdout.readline()
        assert line.startswith("osc: 127.0.0.1:"), line
        client = SimpleUDPClient("127.0.0.1", int(line.rsplit(":", 1)[1]))
        live.wait_stats(lambda s: s["frames"] > 5)
        client.send_message("/swirl", 0.9)
        client.send_message("/nobody", 0.5)  # an address no parameter follows
        live.wait_stats(lambda s: s["controllers"]["messages"] == 2)
        time.sleep(1.2)
        client.send_message("/swirl", 0)  # an int
        stats = live.wait_stats(lambda s: s["controllers"]["messages"] == 3)
        assert stats["controllers"] == {"messages": 3, "unknown": 1, "dropped": 0}
        live.proc.wait(30)  # --duration ends it
    finally:
        rc = live.stop(timeout=60)
    assert rc == 0, live.stderr()
    assert f"wrote {auto}" in live.stderr()
    said = "controllers: 3 messages (1 to names the recipe does not use), 0 dropped"
    assert said in live.stderr()
    doc = json.loads(auto.read_text())
    keys = doc["ops"][0]["alpha"]["keys"]
    assert [k["v"] for k in keys] == pytest.approx([40.0, 360.0, 0.0])  # OSC floats: float32
    assert [k.get("ease") for k in keys] == ["hold", "hold", None]
    changes = [k["t"] for k in keys[1:]]

    marbler = Marbler(parse_recipe(doc), renderer)
    photo = _photo()
    frames = _recording(take)
    checked = 0
    for t, frame in frames:
        if min(abs(t - c) for c in changes) < 0.3:
            continue  # a frame this close to a change may have been rendered either side
        replay = marbler.render(photo, t)[..., :3].astype(int)
        assert np.abs(replay - frame).mean() < 1.0, t
        checked += 1
    assert checked >= 20
    # the take moved: frames before, during and after the swirl differ
    shown = [f for t, f in frames if changes[0] + 0.3 < t < changes[1] - 0.3]
    assert shown and np.abs(shown[0].astype(int) - frames[0][1]).mean() > 10


def test_a_midi_signal_without_the_extra_names_it(tmp_path):
    recipe = tmp_path / "r.json"
    doc = json.loads(json.dumps(RECIPE))
    doc["ops"][0]["alpha"]["signal"] = "midi:cc:1:7"
    recipe.write_text(json.dumps(doc))
    code = (
        "import sys; sys.modules['mido'] = None; sys.modules['rtmidi'] = None\n"
        "from marblevideo.cli import main; sys.exit(main(sys.argv[1:]))"
    )
    r = subprocess.run(
        [sys.executable, "-c", code, "live", "test", "--ops", recipe, "--duration", "1",
         "-o", tmp_path / "x.mp4"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert r.returncode == 2, r.stderr
    assert "marblevideo[midi]" in r.stderr and r.stderr.count("\n") == 1
    assert not (tmp_path / "x.mp4").exists()


def test_bad_controller_options_are_refused_before_starting(cli, tmp_path):
    recipe = tmp_path / "r.json"
    recipe.write_text(json.dumps(RECIPE))
    (tmp_path / "old.json").write_text("{}")
    for args, expected in (
        (["--osc", "host:port"], "--osc: expected [HOST:]PORT"),
        (["--osc", "99999"], "--osc: port must be 0..65535"),
        (["--automation", "old.json"], "old.json: already exists"),
        (["--automation", "r.json", "-y"], "--automation: r.json is also --ops"),
    ):
        r = cli("live", "test", "--ops", recipe, "--duration", "1", *args)
        assert r.returncode == 2, r.stderr
        assert expected in r.stderr and r.stderr.count("\n") == 1, r.stderr


def test_midi_lists_input_ports_or_says_why_not_in_one_line(cli):
    r = cli("midi")
    if r.returncode == 0:  # a system with an ALSA sequencer (or CoreMIDI, WinMM)
        assert r.stderr in ("", "marblevideo: no MIDI input ports\n")
    else:  # no sequencer here (no /dev/snd/seq): a runtime failure, said once
        assert r.returncode == 1, r.stderr
        assert r.stderr.startswith("marblevideo: MIDI: cannot list input ports: ")
        assert r.stderr.count("\n") == 1 and "ALSA lib" not in r.stderr


def test_sigterm_ends_the_session_and_writes_the_take(tmp_path):
    recipe, auto = tmp_path / "r.json", tmp_path / "take.json"
    recipe.write_text(json.dumps(RECIPE))
    live = LiveProcess(
        "test", "--size", "160x90", "--ops", recipe, "--osc", "0", "--automation", auto,
        cwd=tmp_path, preview=False,
    )  # fmt: skip
    try:
        line = live.proc.stdout.readline()
        client = SimpleUDPClient("127.0.0.1", int(line.rsplit(":", 1)[1]))
        time.sleep(1.0)
        client.send_message("/swirl", 0.5)
        time.sleep(0.5)
    finally:
        rc = live.stop(signal.SIGTERM)
    assert rc == 0, live.stderr()
    keys = json.loads(auto.read_text())["ops"][0]["alpha"]["keys"]
    assert [k["v"] for k in keys] == [40.0, 200.0]
    assert 0.5 < keys[1]["t"] < 5
    assert not list(tmp_path.glob(".take.*"))  # no temporary left
