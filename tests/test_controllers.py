"""Controller signals (docs/recipe-format.md, "Signals"): the 100 Hz envelope
against a step-by-step transcription of the contract, OSC over real UDP on
loopback, the MIDI mapping (mido Messages through the port callback's code; no
ALSA sequencer here for a virtual port), and the automation tracks."""

from __future__ import annotations

import math
import socket
import time

import numpy as np
import pytest
from pythonosc.osc_message_builder import OscMessageBuilder
from pythonosc.udp_client import SimpleUDPClient

from marblevideo.controllers.automation import recorded
from marblevideo.controllers.osc import OscListener, message_value, parse_endpoint
from marblevideo.controllers.values import ControllerSignals, SessionSignals
from marblevideo.errors import UsageError
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.signals import Signal

pytestmark = pytest.mark.tier("fast")


def contract(messages, n, initial=0.0, attack=0.0, release=0.0):
    """e_0 .. e_{n-1} as the contract says, one grid step at a time, from
    ``messages`` [(time s, value)] in arrival order."""
    out, e = [], initial
    for i in range(n):
        v = initial
        for s, y in messages:
            if math.floor(100 * s + 1e-9) <= i:
                v = min(1.0, max(0.0, y))
        tau = attack if v > e else release
        c = 1.0 if tau == 0 else 1 - math.exp(-0.01 / tau)
        e = e + c * (v - e)
        out.append(e)
    return np.array(out)


MESSAGES = [(0.013, 0.5), (0.0199, 0.9), (0.31, 1.7), (0.5, 0.2), (0.5004, 0.0), (1.2, 0.6)]


@pytest.mark.parametrize(
    "initial, attack, release", [(0.0, 0.0, 0.0), (0.25, 0.0, 0.0), (0.0, 0.05, 0.3), (0.4, 1, 0)]
)
def test_the_envelope_follows_the_contract(initial, attack, release):
    signals = ControllerSignals()
    for s, y in MESSAGES:
        signals.receive("osc:/a", y, t=s)
    signal = Signal("osc:/a", attack=attack, release=release, initial=initial)
    expected = contract(MESSAGES, 200, initial, attack, release)
    assert np.allclose(signals.envelope(signal, 200), expected, rtol=0, atol=1e-12)
    # read frame by frame, forward (as a session does) and then back again
    times = [0.0, 0.004, 0.02, 0.2, 0.3049, 0.31, 0.77, 1.2, 1.99, 0.5, 0.0]
    for t in times:
        i = math.floor(100 * t + 1e-9)
        assert signals.at(signal, t) == pytest.approx(expected[i], abs=1e-12), t
    assert signals.at(signal, -0.5) == initial


def test_held_values_and_the_last_value_win_within_a_step():
    signals = ControllerSignals()
    signals.receive("osc:/x", 0.3, t=0.101)
    signals.receive("osc:/x", 0.7, t=0.109)  # same step: the last one counts
    plain = Signal("osc:/x")
    assert signals.at(plain, 0.099) == 0.0
    assert signals.at(plain, 0.1) == 0.7
    assert signals.at(plain, 3600.0) == 0.7  # held
    assert signals.latest() == {"osc:/x": 0.7}


def test_unknown_names_are_counted_and_kept():
    signals = ControllerSignals()
    signals.known = frozenset({"osc:/a"})
    signals.receive("osc:/a", 0.5, t=0)
    signals.receive("osc:/b", 0.5, t=0)
    signals.drop()
    assert signals.counts == {"messages": 2, "unknown": 1, "dropped": 1}
    assert signals.at(Signal("osc:/b"), 0.0) == 0.5  # a later binding sees it


def test_session_signals_read_controllers_at_the_session_time():
    now = [0.0]
    signals = ControllerSignals(clock=lambda: now[0])
    bound = SessionSignals(signals)
    signals.receive("midi:cc:1:7", 1.0)  # at 0.0
    now[0] = 2.0
    assert bound.at(Signal("midi:cc:1:7"), 123.0) == 1.0  # the animation's t is not theirs
    assert bound.at(Signal("audio.low"), 1.0) == 0.0  # no audio source: resting


def _listening():
    signals = ControllerSignals()
    return signals, OscListener(signals, "127.0.0.1", 0).start()


def _wait(pred, timeout=5.0):
    end = time.monotonic() + timeout
    while not pred():
        assert time.monotonic() < end, "timed out"
        time.sleep(0.01)


def test_osc_over_udp_sets_the_last_number_clamped():
    signals, osc = _listening()
    try:
        client = SimpleUDPClient("127.0.0.1", osc.port)
        client.send_message("/fader/1", 0.25)
        client.send_message("/fader/2", 3)  # an int, clamped to 1
        client.send_message("/fader/3", -0.5)
        client.send_message("/fader/1", [0.75, "extra"])  # first argument counts
        _wait(lambda: signals.counts["messages"] == 4)
        assert signals.latest() == {"osc:/fader/1": 0.75, "osc:/fader/2": 1.0, "osc:/fader/3": 0.0}
        assert signals.counts["unknown"] == 4  # no recipe uses them
    finally:
        osc.close()


def test_malformed_packets_and_non_numbers_are_dropped():
    signals, osc = _listening()
    try:
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.sendto(b"garbage", ("127.0.0.1", osc.port))
        sock.sendto(b"#bundle\x00\x00", ("127.0.0.1", osc.port))  # a truncated bundle
        builder = OscMessageBuilder("/text")
        builder.add_arg("hello")
        sock.sendto(builder.build().dgram, ("127.0.0.1", osc.port))
        builder = OscMessageBuilder("/flag")
        builder.add_arg(True)
        sock.sendto(builder.build().dgram, ("127.0.0.1", osc.port))
        SimpleUDPClient("127.0.0.1", osc.port).send_message("/ok", 0.5)
        _wait(lambda: signals.counts["messages"] == 1)
        _wait(lambda: signals.counts["dropped"] == 4)
        assert signals.latest() == {"osc:/ok": 0.5}
        sock.close()
    finally:
        osc.close()


def test_message_values_and_endpoints():
    assert message_value([0.5]) == 0.5 and message_value([2]) == 2.0
    assert message_value([]) is None and message_value([float("nan")]) is None
    assert message_value([False]) is None and message_value(["1"]) is None
    assert parse_endpoint("9000") == ("127.0.0.1", 9000)
    assert parse_endpoint("0.0.0.0:9000") == ("0.0.0.0", 9000)
    assert parse_endpoint("[::1]:9000") == ("::1", 9000)
    for bad in ("x", "host:", "70000"):
        with pytest.raises(UsageError, match="--osc"):
            parse_endpoint(bad)


def test_midi_messages_map_through_the_port_callback():
    mido = pytest.importorskip("mido")
    from marblevideo.controllers.midi import deliver

    signals = ControllerSignals()
    for message in (
        mido.Message("control_change", channel=0, control=7, value=127),
        mido.Message("control_change", channel=15, control=1, value=64),
        mido.Message("note_on", channel=2, note=60, velocity=100),
        mido.Message("note_on", channel=2, note=62, velocity=90),
        mido.Message("note_off", channel=2, note=62, velocity=40),
        mido.Message("pitchwheel", channel=0, pitch=100),  # ignored
    ):
        deliver(signals, message)
    assert signals.latest() == {
        "midi:cc:1:7": 1.0,
        "midi:cc:16:1": 64 / 127,
        "midi:note:3:60": 100 / 127,
        "midi:note:3:62": 0.0,
    }
    deliver(signals, mido.Message("note_on", channel=2, note=60, velocity=0))  # released
    assert signals.latest()["midi:note:3:60"] == 0.0


RECIPE = {
    "marblevideo": 1,
    "canvas": [64, 64],
    "ops": [
        {
            "type": "vortex",
            "center": [32, 32],
            "alpha": {"signal": "osc:/swirl", "range": [0, 200], "initial": 0.5},
            "lambda": {"signal": "audio.low", "range": [10, 40]},
        }
    ],
}


def test_automation_tracks_replay_what_the_session_showed():
    signals = ControllerSignals()
    for s, y in [(0.5, 1.0), (0.505, 0.25), (1.0, 0.25), (2.0, 0.0)]:
        signals.receive("osc:/swirl", y, t=s)
    doc = recorded(RECIPE, signals, end=3.0)
    track = doc["ops"][0]["alpha"]
    assert doc["ops"][0]["lambda"] == RECIPE["ops"][0]["lambda"]  # audio stays a signal
    assert track["keys"] == [
        {"t": 0.0, "v": 100.0, "ease": "hold"},
        {"t": 0.5, "v": 50.0, "ease": "hold"},
        {"t": 2.0, "v": 0.0},
    ]  # one key per change: the message at 1.0 changed nothing
    replay = parse_recipe(doc).ops[0].params["alpha"]
    live = parse_recipe(RECIPE).ops[0].params["alpha"]
    for t in np.linspace(0, 3, 301):
        assert replay.at(t) == pytest.approx(live.at(t, signals), abs=1e-9), t


def test_automation_of_an_envelope_keeps_at_most_100_keys_a_second():
    signals = ControllerSignals()
    signals.receive("osc:/swirl", 1.0, t=0.2)
    doc = {**RECIPE, "ops": [{**RECIPE["ops"][0]}]}
    doc["ops"][0]["alpha"] = {"signal": "osc:/swirl", "range": [0, 200], "attack": 0.1}
    keys = recorded(doc, signals, end=2.0)["ops"][0]["alpha"]["keys"]
    times = [k["t"] for k in keys]
    assert times[0] == 0.0 and times[1] == 0.2 and len(times) <= 201
    assert all(b - a >= 0.01 - 1e-12 for a, b in zip(times, times[1:], strict=False))
    replay = parse_recipe(doc | {"ops": recorded(doc, signals, 2.0)["ops"]}).ops[0]
    live = parse_recipe(doc).ops[0].params["alpha"]
    for t in np.linspace(0, 2, 201):
        assert replay.params["alpha"].at(t) == pytest.approx(live.at(t, signals), abs=1e-6)


def test_learn_takes_the_next_name_received():
    signals = ControllerSignals()
    signals.receive("osc:/before", 0.1)
    assert signals.learned is None
    signals.learn()
    assert signals.learning
    signals.receive("midi:cc:2:74", 0.5)
    signals.receive("osc:/after", 0.5)
    assert signals.learned == "midi:cc:2:74" and not signals.learning


def test_reads_interleaved_with_messages_equal_the_contract_on_the_whole_log():
    """A frame may read a step before a message of that same step arrives; later
    reads (and the take) then follow the contract on the whole log."""
    signals = ControllerSignals()
    signal = Signal("osc:/e", attack=0.03, release=0.2, initial=0.1)
    rng = np.random.default_rng(7)
    sent = []
    t = 0.0
    for _ in range(400):
        t += float(rng.uniform(0, 0.03))
        if rng.random() < 0.3:
            y = float(rng.uniform(-0.2, 1.2))
            signals.receive("osc:/e", y, t=t)
            sent.append((t, y))
        back = t - float(rng.uniform(0, 2.5)) if rng.random() < 0.1 else t  # a meter's late read
        expected = contract(sent, math.floor(100 * max(back, 0) + 1e-9) + 1, 0.1, 0.03, 0.2)
        assert signals.at(signal, back) == pytest.approx(expected[-1], abs=1e-12)
    end = math.floor(100 * t + 1e-9) + 1
    assert np.allclose(signals.envelope(signal, end), contract(sent, end, 0.1, 0.03, 0.2))
