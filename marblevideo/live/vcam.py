"""A virtual camera: frames sent to pyvirtualcam (the optional extra ``vcam``)."""

from __future__ import annotations

import threading

import numpy as np

from marblevideo.errors import MarbleError
from marblevideo.live.sources import Latest

VCAM_HELP = (
    "pip install 'marblevideo[vcam]' (pyvirtualcam), and on Linux a v4l2loopback device: "
    "sudo apt-get install v4l2loopback-dkms && "
    "sudo modprobe v4l2loopback devices=1 exclusive_caps=1"
)


class VirtualCamera:
    """Frames to a virtual camera through pyvirtualcam (optional extra ``vcam``)."""

    def __init__(self, width: int, height: int, fps: float):
        try:
            import pyvirtualcam
        except ImportError:
            raise MarbleError(f"--vcam needs pyvirtualcam: {VCAM_HELP}") from None
        try:
            self.cam = pyvirtualcam.Camera(width, height, fps, fmt=pyvirtualcam.PixelFormat.RGB)
        except Exception as exc:  # noqa: BLE001 - the library raises RuntimeError and others
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise MarbleError(f"--vcam: no virtual camera device ({first}); {VCAM_HELP}") from None
        self.frames = Latest()
        self._thread = threading.Thread(target=self._run, name="marblevideo-vcam", daemon=True)
        self._thread.start()

    def send(self, rgba: np.ndarray) -> None:
        self.frames.put(rgba)

    def _run(self) -> None:
        while (rgba := self.frames.get()) is not None:
            self.cam.send(np.ascontiguousarray(rgba[..., :3]))

    def close(self) -> None:
        self.frames.close()
        self._thread.join(2.0)
        self.cam.close()
