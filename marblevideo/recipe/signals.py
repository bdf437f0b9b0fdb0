"""Signals (docs/recipe-format.md, "Signals", revision 3): a number parameter
that follows the sound or a controller instead of keyframes.

A parameter given as ``{"signal": NAME, "range": [lo, hi], ...}`` is a
:class:`SignalTrack`: at time t (seconds from the first frame) it is
lo + (hi - lo) * y, where y in 0..1 is what a :class:`SignalValues` source says
the :class:`Signal` is at t. Audio sources (:mod:`marblevideo.signals`) and live
controllers plug in through that one method, ``at(signal, t)``.

Names: ``audio.level``, ``audio.low``, ``audio.mid``, ``audio.high`` (audio
signals, options ``db``, ``attack``, ``release``); ``osc:/ADDRESS``,
``midi:cc:CH:N`` and ``midi:note:CH:N`` (controller signals, channel 1..16,
number 0..127, options ``initial``, ``attack``, ``release``). Attack and
release are seconds; db is [d0, d1] in dB full scale.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from typing import Protocol

from marblevideo.recipe.keyframes import Track

#: The audio bands, as signal names.
AUDIO_NAMES = ("audio.level", "audio.low", "audio.mid", "audio.high")
#: The forms a controller signal's name takes, for messages.
CONTROLLER_FORMS = ("osc:/ADDRESS", "midi:cc:CH:N", "midi:note:CH:N")
#: Every form of a name, for messages.
NAME_FORMS = (*AUDIO_NAMES, *CONTROLLER_FORMS)
#: Default ``db`` of an audio signal: [d0, d1].
DEFAULT_DB = (-60.0, 0.0)
#: Which optional fields each source of signal takes (besides ``signal`` and ``range``).
OPTIONS = {"audio": ("db", "attack", "release"), "osc": ("initial", "attack", "release")}
OPTIONS["midi"] = OPTIONS["osc"]

# An OSC address: "/" then printable ASCII without space and the pattern characters.
_OSC = re.compile(r"osc:(/[!-~]*)")
_OSC_BAD = re.compile(r"[\s#*,?\[\]{}]")
_MIDI = re.compile(r"midi:(cc|note):(\d{1,2}):(\d{1,3})")


@dataclass(frozen=True)
class Signal:
    """One signal as a recipe uses it: its ``name`` and options. Hashable: a
    source may keep one envelope per distinct signal."""

    name: str
    db: tuple[float, float] = DEFAULT_DB
    attack: float = 0.0
    release: float = 0.0
    initial: float = 0.0

    @property
    def source(self) -> str:
        """``audio``, ``osc`` or ``midi``."""
        return "audio" if self.name.startswith("audio.") else self.name.split(":", 1)[0]

    @property
    def band(self) -> str:
        """An audio signal's band: ``level``, ``low``, ``mid`` or ``high``."""
        return self.name.split(".", 1)[1]

    @property
    def controller(self) -> bool:
        """Whether it exists only in a live session (OSC, MIDI)."""
        return self.source != "audio"

    @property
    def osc_address(self) -> str:
        return self.name[4:]

    @property
    def midi(self) -> tuple[str, int, int]:
        """(``cc`` or ``note``, channel 1..16, controller or note 0..127)."""
        kind, channel, number = _MIDI.fullmatch(self.name).groups()
        return kind, int(channel), int(number)

    def resting(self) -> float:
        """y before anything is heard or sent: 0 for audio, ``initial`` for controllers."""
        return self.initial if self.controller else 0.0


def name_fault(name: str) -> str | None:
    """Why ``name`` is not a signal name, or None when it is one."""
    if name in AUDIO_NAMES:
        return None
    if name.startswith("osc:"):
        match = _OSC.fullmatch(name)
        if match is None or len(name) == 5 or _OSC_BAD.search(match.group(1)):
            return (
                f"expected an OSC address osc:/ADDRESS (printable ASCII after the /, no spaces "
                f"or pattern characters #*,?[]{{}}), got string {name!r}"
            )
        return None
    if name.startswith("midi:"):
        match = _MIDI.fullmatch(name)
        if match is None:
            return f"expected midi:cc:CH:N or midi:note:CH:N (whole numbers), got string {name!r}"
        _, channel, number = match.groups()
        if not 1 <= int(channel) <= 16:
            return f"MIDI channel must be 1..16, got {int(channel)} in {name!r}"
        if not 0 <= int(number) <= 127:
            return f"MIDI controller or note must be 0..127, got {int(number)} in {name!r}"
        return None
    close = difflib.get_close_matches(name, AUDIO_NAMES, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return f"unknown signal {name!r}{hint}; expected {', '.join(NAME_FORMS)}"


def signal_faults(value: dict) -> list[tuple[list, str]]:
    """What the schema cannot say about one signal object (structurally valid):
    (JSON path below it, message) pairs."""
    name = value["signal"]
    fault = name_fault(name)
    if fault is not None:
        return [(["signal"], fault)]
    signal = Signal(name)
    faults = []
    for option in ("db", "initial"):
        if option in value and option not in OPTIONS[signal.source]:
            kind = "an audio" if option == "db" else "a controller"
            faults.append(([option], f"{kind} signal's option; {name} takes no {option}"))
    if "db" in value and value["db"][0] >= value["db"][1]:
        d0, d1 = value["db"]
        faults.append((["db"], f"must be [d0, d1] with d0 < d1, got [{d0:g}, {d1:g}]"))
    return faults


class SignalValues(Protocol):
    """A source of signal values: y in 0..1 of ``signal`` at time ``t`` (seconds
    from the first frame). Audio analyses and live controllers implement it."""

    def at(self, signal: Signal, t: float) -> float: ...


@dataclass(frozen=True)
class SignalTrack:
    """A number parameter that follows ``signal``: lo + (hi - lo) * y.

    It has no keys (``key_times`` is empty, so it adds nothing to a recipe's end
    time) but ``varies``. Without a source (``signals`` None) y is the signal's
    resting value (:meth:`Signal.resting`).
    """

    signal: Signal
    lo: float
    hi: float
    scalar: bool = True
    keyed: bool = False
    varies: bool = True
    key_times: tuple[float, ...] = ()

    def at(self, t: float, signals: SignalValues | None = None) -> float:
        y = self.signal.resting() if signals is None else signals.at(self.signal, t)
        return self.lo + (self.hi - self.lo) * y

    def json(self) -> dict:
        """The signal object as a recipe writes it (defaults left out)."""
        s = self.signal
        out: dict = {"signal": s.name, "range": [self.lo, self.hi]}
        if s.db != DEFAULT_DB:
            out["db"] = list(s.db)
        for option in ("attack", "release", "initial"):
            if getattr(s, option):
                out[option] = getattr(s, option)
        return out


def signal_track(value: dict) -> SignalTrack:
    """A valid signal object as a :class:`SignalTrack`."""
    lo, hi = (float(c) for c in value["range"])
    d0, d1 = value.get("db", DEFAULT_DB)
    signal = Signal(
        value["signal"],
        db=(float(d0), float(d1)),
        attack=float(value.get("attack", 0.0)),
        release=float(value.get("release", 0.0)),
        initial=float(value.get("initial", 0.0)),
    )
    return SignalTrack(signal, lo, hi)


def check_at_ends(check, op: dict, tracks: dict) -> list[tuple[list, str]]:
    """An op's own ``check`` (:class:`~marblevideo.ops.base.OpDef`) where some of its
    parameters follow signals: run with each signal at the low end of its range,
    then at the high end; a fault on such a parameter points at that end
    (``major.range[1]``)."""
    signals = {n for n, t in tracks.items() if isinstance(t, SignalTrack)}
    if not signals:
        return check(op, tracks)
    for end in (0, 1):
        ends = {
            n: Track.constant((t.lo, t.hi)[end]) if n in signals else t for n, t in tracks.items()
        }
        found = check(op, ends)
        if found:
            return [
                ([p[0], "range", end, *p[1:]] if p and p[0] in signals else p, m) for p, m in found
            ]
    return []
