"""NDI out: the frames of a live session sent as an NDI source (the optional
extra ``ndi``: cyndilib, the NDI runtime bundled), which OBS (with its NDI
plugin), vMix, Resolume and TouchDesigner receive.

The source is named ``NAME`` on this machine; receivers list it as
``MACHINE (NAME)``. Frames go as RGBA at the source's size, with its nominal
rate and the SDK's synthesized timecodes, from their own thread behind a
one-slot mailbox (a slow receiver drops frames, never the session). Sound is
not sent: a live session's frames carry none.

Discovery is NDI's mDNS; where multicast does not pass (containers, some
networks), NDI's configuration (``NDI_CONFIG_DIR``/ndi-config.v1.json,
``{"ndi": {"networks": {"ips": "127.0.0.1"}}}``) gives the addresses to ask.
"""

from __future__ import annotations

import threading
from fractions import Fraction

import numpy as np

from marblevideo.errors import UsageError
from marblevideo.live.sources import Latest

NDI_HELP = "pip install 'marblevideo[ndi]' (cyndilib, the NDI runtime bundled)"


def check_ndi(name: str) -> None:
    """UsageError (one line, exit 2) without the extra, or for an empty name."""
    if not name.strip():
        raise UsageError("--ndi: give the source a name")
    try:
        import cyndilib  # noqa: F401 - checked before anything opens
    except ImportError:
        raise UsageError(f"--ndi needs the extra ndi: {NDI_HELP}") from None


class NdiSender:
    """An NDI source named ``name`` sending RGBA frames of ``width`` x ``height``."""

    def __init__(self, name: str, width: int, height: int, fps: float):
        from cyndilib import FourCC, Sender, VideoSendFrame

        self.name = name
        self.sent = 0
        self.sender = Sender(name)
        frame = VideoSendFrame()
        frame.set_resolution(width, height)
        frame.set_frame_rate(Fraction(fps).limit_denominator(1001))
        frame.set_fourcc(FourCC.RGBA)
        self.sender.set_video_frame(frame)
        self.sender.open()
        self.frames = Latest()
        self._thread = threading.Thread(target=self._run, name="marblevideo-ndi", daemon=True)
        self._thread.start()

    @property
    def full_name(self) -> str:
        """The name receivers list: ``MACHINE (NAME)``."""
        source = self.sender.source
        return source.name if source is not None else self.name

    def send(self, rgba: np.ndarray) -> None:
        self.frames.put(rgba)

    def _run(self) -> None:
        while (rgba := self.frames.get()) is not None:
            self.sender.write_video(np.ascontiguousarray(rgba).reshape(-1))
            self.sent += 1

    def figures(self) -> dict:
        """What ``/stats`` shows of the NDI source."""
        return {
            "name": self.full_name,
            "sent": self.sent,
            "dropped": self.frames.dropped,
            "connections": self.sender.get_num_connections(0),
        }

    def close(self) -> None:
        self.frames.close()
        self._thread.join(2.0)
        self.sender.close()
