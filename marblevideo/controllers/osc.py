"""OSC over UDP (``marblevideo live --osc [HOST:]PORT``): each message's first
argument, when it is a number (int or float), sets signal ``osc:ADDRESS`` to it
(clamped to 0..1, :class:`~marblevideo.controllers.values.ControllerSignals`).

Packets are decoded by python-osc (messages and bundles; a bundle's time tag is
ignored: a value counts when it arrives). A packet that does not decode, or a
message with no numeric first argument, is dropped and counted, never raised.
"""

from __future__ import annotations

import math
import socket
import threading

from pythonosc.osc_packet import OscPacket

from marblevideo.controllers.values import ControllerSignals
from marblevideo.errors import UsageError

DEFAULT_HOST = "127.0.0.1"
MAX_PACKET = 65536


def parse_endpoint(text: str) -> tuple[str, int]:
    """``[HOST:]PORT`` as (host, port); UsageError naming --osc when it is not one."""
    host, _, port = text.rpartition(":")
    host = host.strip("[]") or DEFAULT_HOST
    try:
        number = int(port)
    except ValueError:
        raise UsageError(f"--osc: expected [HOST:]PORT, got {text!r}") from None
    if not 0 <= number <= 65535:
        raise UsageError(f"--osc: port must be 0..65535, got {number}")
    return host, number


def message_value(args) -> float | None:
    """The number a message sets: its first argument if it is an int or a finite
    float (not a bool), else None."""
    if not args:
        return None
    value = args[0]
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value) if math.isfinite(value) else None


class OscListener:
    """A UDP socket on (host, port) read by a daemon thread into ``signals``."""

    def __init__(self, signals: ControllerSignals, host: str = DEFAULT_HOST, port: int = 0):
        self.signals = signals
        family = socket.AF_INET6 if ":" in host else socket.AF_INET
        self.sock = socket.socket(family, socket.SOCK_DGRAM)
        try:
            self.sock.bind((host, port))
        except OSError as exc:
            self.sock.close()
            raise UsageError(f"--osc: cannot listen on {host}:{port}: {exc.strerror}") from None
        self.sock.settimeout(0.2)
        self.address = self.sock.getsockname()[:2]
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="marblevideo-osc", daemon=True)

    @property
    def port(self) -> int:
        return self.address[1]

    def start(self) -> OscListener:
        self._thread.start()
        return self

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                data, _ = self.sock.recvfrom(MAX_PACKET)
            except TimeoutError:
                continue
            except OSError:
                if self._stop.is_set():
                    return
                continue
            self.handle(data)

    def handle(self, data: bytes) -> None:
        """One datagram: every message in it, or one drop when it does not decode."""
        try:
            messages = [m.message for m in OscPacket(data).messages]
        except Exception:  # noqa: BLE001 - any undecodable packet is dropped, never raised
            self.signals.drop()
            return
        for message in messages:
            value = message_value(message.params)
            if value is None:
                self.signals.drop()
            else:
                self.signals.receive(f"osc:{message.address}", value)

    def close(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(2.0)
        self.sock.close()
