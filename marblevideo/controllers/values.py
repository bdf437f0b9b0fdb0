"""Controller signal values (docs/recipe-format.md, "Signals": controller
signals): what OSC and MIDI messages set, as a
:class:`~marblevideo.recipe.signals.SignalValues` source.

Time is the session's clock: seconds since the live session started
(monotonic wall clock; pausing or seeking the animation clock does not move
it). A message received at time s takes effect on the 100 Hz grid at step
k = floor(100 s + 1e-9), so a frame rendered after it always shows it. For a
signal with ``initial`` y0, ``attack`` and ``release``:

- v_i is the value of the last message to its name at a step <= i (y0 before
  the first one);
- e_{-1} = y0; e_i = e_{i-1} + c (v_i - e_{i-1}) with c = 1 - exp(-0.01 / tau),
  tau = attack when v_i > e_{i-1}, else release (tau = 0: c = 1);
- at time t, y = e_i with i = floor(100 t + 1e-9).

Every message is kept (the last one per name and step), so the whole take can
be written back as keyframes (:mod:`marblevideo.controllers.automation`).
"""

from __future__ import annotations

import math
import threading
import time
from bisect import bisect_right
from dataclasses import dataclass, field

import numpy as np

from marblevideo.recipe.signals import Signal
from marblevideo.signals.levels import RATE, coefficient, held


def step(t: float) -> int:
    """The grid step of time ``t`` (seconds): floor(100 t + 1e-9)."""
    return math.floor(RATE * t + 1e-9)


def clamp01(value: float) -> float:
    return min(1.0, max(0.0, float(value)))


@dataclass
class _Log:
    """One name's messages: steps (non-decreasing) and values, one per step."""

    steps: list[int] = field(default_factory=list)
    values: list[float] = field(default_factory=list)

    def add(self, k: int, y: float) -> None:
        if self.steps and k <= self.steps[-1]:  # same step (or a clock that went back)
            self.values[-1] = y
            return
        self.steps.append(k)
        self.values.append(y)

    def value(self, i: int, initial: float) -> float:
        """v_i: the last value at a step <= i."""
        n = bisect_right(self.steps, i)
        return self.values[n - 1] if n else initial


class ControllerSignals:
    """The values of controller signals, fed by listeners through :meth:`receive`
    (any thread) and read through :meth:`at` (the :class:`SignalValues` interface).

    ``clock`` gives the session's time in seconds; :meth:`start` sets its zero.
    ``known`` holds the names the running recipe uses; messages to other names
    are kept (a later binding may use them) and counted in ``unknown``.
    """

    def __init__(self, clock=None):
        self._origin = time.monotonic()
        self._clock = clock or (lambda: time.monotonic() - self._origin)
        self._lock = threading.Lock()
        self._logs: dict[str, _Log] = {}
        # signal -> [(i, e_i)], i increasing: one a second and the last one asked
        self._states: dict[Signal, list[tuple[int, float]]] = {}
        self.known: frozenset[str] = frozenset()
        self.counts = {"messages": 0, "unknown": 0, "dropped": 0}
        self.learning = False  # learn: the next name received becomes ``learned``
        self.learned: str | None = None

    def start(self, origin: float | None = None) -> None:
        """The session starts at ``origin`` (``time.monotonic()``; default now):
        t = 0 there (messages before are forgotten)."""
        with self._lock:
            self._origin = time.monotonic() if origin is None else origin
            self._logs.clear()
            self._states.clear()

    def now(self) -> float:
        return self._clock()

    def receive(self, name: str, y: float, t: float | None = None) -> None:
        """A message: signal ``name`` is ``y`` (clamped to 0..1) from time ``t``
        (default: now)."""
        k = step(self.now() if t is None else t)
        with self._lock:
            self.counts["messages"] += 1
            if name not in self.known:
                self.counts["unknown"] += 1
            self._logs.setdefault(name, _Log()).add(k, clamp01(y))
            for signal, states in self._states.items():  # e_i from step k on changed
                if signal.name == name:
                    del states[bisect_right(states, (k - 1, math.inf)) :]
            if self.learning:
                self.learning, self.learned = False, name

    def learn(self) -> None:
        """Take the name of the next message received as :attr:`learned`."""
        with self._lock:
            self.learning, self.learned = True, None

    def drop(self) -> None:
        """Count a malformed message (or one with no number)."""
        with self._lock:
            self.counts["dropped"] += 1

    def latest(self) -> dict[str, float]:
        """The last value received per name."""
        with self._lock:
            return {name: log.values[-1] for name, log in self._logs.items()}

    def at(self, signal: Signal, t: float) -> float:
        """y of ``signal`` at session time ``t`` (seconds)."""
        i = step(t)
        if i < 0:
            return signal.initial
        with self._lock:
            log = self._logs.get(signal.name, _Log())
            states = self._states.setdefault(signal, [])
            n = bisect_right(states, (i, math.inf))  # the last state at or before i
            j, e = states[n - 1] if n else (-1, signal.initial)
            e = _advance(log, signal, j, e, i)
            if n == len(states) and i > j:
                if len(states) >= 2 and states[-1][0] - states[-2][0] < RATE:
                    states[-1] = (i, e)
                else:
                    states.append((i, e))
            return e

    def envelope(self, signal: Signal, end: int) -> np.ndarray:
        """e_i for i = 0 .. end - 1."""
        with self._lock:
            log = self._logs.get(signal.name, _Log())
            steps, values = np.array(log.steps, np.int64), np.array(log.values, np.float64)
        last = np.searchsorted(steps, np.arange(end), side="right") - 1
        v = np.where(last >= 0, values[np.maximum(last, 0)] if len(values) else 0.0, signal.initial)
        return envelope_from(v, signal.initial, signal.attack, signal.release)


def _advance(log: _Log, signal: Signal, j: int, e: float, i: int) -> float:
    """e_i from e_j (j < i, or j = i: e unchanged), step by step between messages
    and in closed form (:func:`~marblevideo.signals.levels.held`) across a hold."""
    if signal.attack == signal.release == 0.0:
        return log.value(i, signal.initial) if i > j else e
    n = bisect_right(log.steps, j)
    while j < i:
        v = log.value(j + 1, signal.initial)
        nxt = log.steps[n] if n < len(log.steps) else i + 1
        stop = min(i, max(nxt - 1, j + 1))  # v holds from j + 1 to stop
        e = held(e, v, stop - j, signal.attack, signal.release)
        j = stop
        while n < len(log.steps) and log.steps[n] <= j:
            n += 1
    return e


def envelope_from(v: np.ndarray, e0: float, attack: float, release: float) -> np.ndarray:
    """e_i = e_{i-1} + c (v_i - e_{i-1}) from e_{-1} = ``e0``."""
    v = np.asarray(v, dtype=np.float64)
    up, down = coefficient(attack), coefficient(release)
    if up == down == 1.0:
        return v.copy()
    out = np.empty(len(v))
    e = e0
    for i, x in enumerate(v.tolist()):
        e += (up if x > e else down) * (x - e)
        out[i] = e
    return out


class SessionSignals:
    """The recipe's signal source in a live session: controller signals at the
    session's time now (the ``t`` a frame is rendered at, the animation clock,
    is not theirs: it may be paused, seeked or looped), other sources as given."""

    def __init__(self, controllers: ControllerSignals, others=None):
        self.controllers = controllers
        self.others = others

    def at(self, signal: Signal, t: float) -> float:
        if signal.controller:
            return self.controllers.at(signal, self.controllers.now())
        if self.others is None:
            return signal.resting()
        return self.others.at(signal, t)
