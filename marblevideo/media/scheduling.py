"""Encoders kept from making this process real-time.

SVT-AV1 (``libsvtav1``), run as root, turns the thread that opens it and every
thread it starts to SCHED_FIFO at priority 99. On a machine with few cores its
busy threads then starve everything else: this process' other stages, and any
program it starts (children inherit the policy). :func:`ordinary_scheduling`
puts back every thread of this process that turned real-time while its block
ran, to the policy the calling thread had before. Linux only; elsewhere, or in
a process made real-time on purpose (the caller's thread already is), it does
nothing.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator

_REALTIME = {getattr(os, "SCHED_FIFO", None), getattr(os, "SCHED_RR", None)} - {None}


def _policy(tid: int) -> int | None:
    try:
        return os.sched_getscheduler(tid)
    except OSError:  # the thread has ended
        return None


def _threads() -> list[int]:
    try:
        return [int(tid) for tid in os.listdir("/proc/self/task")]
    except OSError:
        return []


def realtime_threads() -> list[int]:
    """The ids of this process' threads scheduled real-time (FIFO or round-robin)."""
    if not hasattr(os, "sched_getscheduler"):
        return []
    return [tid for tid in _threads() if _policy(tid) in _REALTIME]


@contextlib.contextmanager
def ordinary_scheduling() -> Iterator[None]:
    """Run the block, then put the threads it made real-time back to the calling
    thread's policy (see the module)."""
    policy = _policy(0) if hasattr(os, "sched_getscheduler") else None
    if policy is None or policy in _REALTIME:
        yield
        return
    param = os.sched_getparam(0)
    before = set(realtime_threads())
    try:
        yield
    finally:
        for tid in realtime_threads():
            if tid not in before:
                with contextlib.suppress(OSError):
                    os.sched_setscheduler(tid, policy, param)
