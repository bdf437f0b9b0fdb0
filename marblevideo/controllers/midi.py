"""MIDI input (``marblevideo live --midi [PORT]``, ``marblevideo midi``) through
mido with the python-rtmidi backend, the optional extra ``marblevideo[midi]``.

Mapping (channels 1..16 as the recipe writes them; mido counts 0..15):
``control_change`` sets ``midi:cc:CH:N`` to value / 127; ``note_on`` with a
velocity > 0 sets ``midi:note:CH:N`` to velocity / 127, and ``note_off`` (or
``note_on`` with velocity 0, the running-status form) sets it to 0. Other
messages (clock, pitch bend, sysex...) are ignored.
"""

from __future__ import annotations

from marblevideo.controllers.values import ControllerSignals
from marblevideo.errors import MarbleError, UsageError
from marblevideo.media.encoders import stderr_silenced

EXTRA = "marblevideo[midi]"
HELP = f"MIDI needs the extra {EXTRA}: pip install '{EXTRA}' (mido and python-rtmidi)"


def message_signal(message) -> tuple[str, float] | None:
    """(signal name, y in 0..1) that a mido Message sets, or None."""
    kind = message.type
    if kind == "control_change":
        return f"midi:cc:{message.channel + 1}:{message.control}", message.value / 127
    if kind in ("note_on", "note_off"):
        velocity = message.velocity if kind == "note_on" else 0
        return f"midi:note:{message.channel + 1}:{message.note}", velocity / 127
    return None


def deliver(signals: ControllerSignals, message) -> None:
    """What the port's callback does with one mido Message."""
    mapped = message_signal(message)
    if mapped is not None:
        signals.receive(*mapped)


def mido_backend():
    """mido with the rtmidi backend; UsageError naming the extra when either is missing."""
    try:
        import mido
        import rtmidi  # noqa: F401 - the backend mido is told to use
    except ImportError:
        raise UsageError(HELP) from None
    mido.set_backend("mido.backends.rtmidi", load=True)
    return mido


def input_names() -> list[str]:
    """The MIDI input ports; MarbleError (exit 1) when the system has no MIDI."""
    mido = mido_backend()
    try:
        with stderr_silenced():  # ALSA prints its own lines without a sequencer
            return list(mido.get_input_names())
    except Exception as exc:  # noqa: BLE001 - rtmidi raises its own SystemError kinds
        raise MarbleError(f"MIDI: cannot list input ports: {_first_line(exc)}") from None


def _first_line(exc: BaseException) -> str:
    return (str(exc).strip().splitlines() or [type(exc).__name__])[0]


def pick_port(port: str | None) -> str:
    """The input port ``--midi`` names (None: the first); UsageError naming the
    ports when there is no such one, MarbleError when there is none at all."""
    names = input_names()
    if not names:
        raise MarbleError("--midi: no MIDI input port (see `marblevideo midi`)")
    if port is None:
        return names[0]
    if port not in names:
        raise UsageError(f"--midi: no input port {port!r}; ports: {', '.join(names)}")
    return port


class MidiInput:
    """An open MIDI input port whose messages set controller signals (mido calls
    :meth:`handle` from its own thread)."""

    def __init__(self, signals: ControllerSignals, port: str | None = None):
        self.signals = signals
        self.name = port = pick_port(port)
        mido = mido_backend()
        try:
            with stderr_silenced():  # ALSA prints its own lines without a sequencer
                self.port = mido.open_input(port, callback=self.handle)
        except Exception as exc:  # noqa: BLE001 - rtmidi's own error kinds
            raise MarbleError(f"--midi: cannot open {port!r}: {_first_line(exc)}") from None

    def handle(self, message) -> None:
        """One mido Message (the port's callback)."""
        deliver(self.signals, message)

    def close(self) -> None:
        self.port.close()
