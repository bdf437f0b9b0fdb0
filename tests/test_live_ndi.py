"""NDI out (``live --ndi NAME``, the extra ``ndi``: cyndilib): a sender runs and
announces itself, and a receiver on this machine gets the frames the preview
shows. Receivers find the source through NDI's unicast discovery on 127.0.0.1
(ndi-config.v1.json's ``ips``); mDNS discovery is tried on its own and skipped,
with the reason, where the network passes no multicast."""

from __future__ import annotations

import json
import subprocess
import sys
import time

import cv2
import numpy as np
import pytest
from helpers import one_line, subprocess_env
from live_helpers import LiveProcess

pytestmark = pytest.mark.tier("integration")

STILL = {
    "marblevideo": 1,
    "ops": [{"type": "vortex", "center": [80, 48], "alpha": 160, "lambda": 40}],
}
SIZE = (160, 96)


def grid(path) -> np.ndarray:
    """A still source: a ramp under a white grid (BGR, as OpenCV writes it)."""
    image = np.zeros((SIZE[1], SIZE[0], 3), np.uint8)
    image[:, :, 2] = np.linspace(0, 200, SIZE[0])[None]
    image[::12], image[:, ::12] = 255, 255
    cv2.imwrite(str(path), image)
    return image


@pytest.fixture
def unicast(tmp_path, monkeypatch):
    """NDI told to ask 127.0.0.1 for sources (this process and its children)."""
    folder = tmp_path / "ndi"
    folder.mkdir()
    config = {"ndi": {"networks": {"ips": "127.0.0.1"}}}
    (folder / "ndi-config.v1.json").write_text(json.dumps(config))
    monkeypatch.setenv("NDI_CONFIG_DIR", str(folder))
    return folder


def find(name: str, timeout: float):
    """The NDI source whose name ends with ``(name)``, or None after ``timeout`` s."""
    from cyndilib import Finder

    finder = Finder()
    finder.open()
    end = time.monotonic() + timeout
    try:
        while time.monotonic() < end:
            finder.wait_for_sources(0.5)
            for full in finder.get_source_names():
                if full.endswith(f"({name})"):
                    return finder.get_source(full)
        return None
    finally:
        finder.close()


def receive(source, timeout: float = 10.0) -> np.ndarray:
    """One RGBA frame from ``source``."""
    from cyndilib import Receiver, RecvBandwidth, RecvColorFormat, VideoRecvFrame
    from cyndilib.receiver import ReceiveFrameType

    receiver = Receiver(color_format=RecvColorFormat.RGBX_RGBA, bandwidth=RecvBandwidth.highest)
    frame = VideoRecvFrame()
    receiver.set_video_frame(frame)
    receiver.set_source(source)
    end = time.monotonic() + timeout
    try:
        while time.monotonic() < end:
            if receiver.receive(ReceiveFrameType.recv_video, 200) & ReceiveFrameType.recv_video:
                width, height = frame.get_resolution()
                return np.asarray(frame).reshape(height, width, 4).copy()
        raise AssertionError("no NDI frame received")
    finally:
        receiver.disconnect()


def test_without_the_extra_one_line_names_it_and_exit_2(tmp_path):
    (tmp_path / "still.json").write_text(json.dumps(STILL))
    code = (
        "import sys; sys.modules['cyndilib'] = None; from marblevideo.cli import main; "
        "sys.exit(main(['live', 'test', '--ops', 'still.json', '--ndi', 'x', '--duration', '1']))"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code],
        cwd=tmp_path,
        env=subprocess_env(),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2
    assert "marblevideo[ndi]" in one_line(proc)


def test_a_receiver_gets_the_frames_the_preview_shows(tmp_path, unicast):
    pytest.importorskip("cyndilib", reason="the extra ndi: pip install 'marblevideo[ndi]'")
    source_image = grid(tmp_path / "grid.png")
    (tmp_path / "still.json").write_text(json.dumps(STILL))
    args = ["grid.png", "--loop", "--ops", "still.json", "--ndi", "marble-test", "--preview"]
    live = LiveProcess(*args, "--port", "0", "--duration", "60", cwd=tmp_path)
    try:
        live.wait_stats(lambda s: s["ndi"]["sent"] > 5, timeout=60)
        source = find("marble-test", 15)
        assert source is not None, "the NDI source was not announced on 127.0.0.1"
        got = receive(source)
        stats = live.get("/stats")
        jpeg = live.get("/frame.jpg")
    finally:
        rc = live.stop()
    assert rc == 0, live.stderr()
    assert "NDI: sending as" in live.stderr() and "(marble-test)" in live.stderr()
    assert stats["ndi"]["name"].endswith("(marble-test)")
    assert got.shape == (SIZE[1], SIZE[0], 4)
    preview = cv2.cvtColor(cv2.imdecode(np.frombuffer(jpeg, np.uint8), 1), cv2.COLOR_BGR2RGB)
    to_preview = np.abs(got[..., :3].astype(int) - preview).mean()
    to_source = np.abs(got[..., :3].astype(int) - source_image[..., ::-1]).mean()
    # both lossy (NDI's SpeedHQ, the preview's JPEG) on a sharp grid: close, and far from
    # the source unmarbled
    assert to_preview < 12 and to_source > 5 * to_preview, (to_preview, to_source)


MDNS_SENDER = """
import time
from fractions import Fraction
from cyndilib import FourCC, Sender, VideoSendFrame
sender = Sender("marble-mdns")
frame = VideoSendFrame()
frame.set_resolution(16, 16)
frame.set_frame_rate(Fraction(10))
frame.set_fourcc(FourCC.RGBA)
sender.set_video_frame(frame)
sender.open()
end = time.monotonic() + 12
while time.monotonic() < end:
    sender.write_video(bytes(16 * 16 * 4))
    time.sleep(0.1)
sender.close()
"""


def test_mdns_discovery_finds_the_sender_where_the_network_allows(monkeypatch):
    pytest.importorskip("cyndilib", reason="the extra ndi: pip install 'marblevideo[ndi]'")
    monkeypatch.delenv("NDI_CONFIG_DIR", raising=False)
    sender = subprocess.Popen([sys.executable, "-c", MDNS_SENDER], env=subprocess_env())
    try:
        found = find("marble-mdns", 6)
    finally:
        sender.kill()
        sender.wait()
    if found is None:
        pytest.skip(
            "NDI's mDNS discovery (multicast 224.0.0.251:5353) found no source in 6 s: this "
            "sandbox's network passes no multicast; test_a_receiver_gets_the_frames_the_"
            "preview_shows receives through NDI's unicast discovery on 127.0.0.1 instead"
        )
    assert found.name.endswith("(marble-mdns)")
