"""Interrupting a real marblevideo process, as a user's Ctrl-C or a kill does."""

from __future__ import annotations

import subprocess
import time
from collections.abc import Callable


def wait_until(proc: subprocess.Popen, ready: Callable[[], bool], seconds: float) -> None:
    """Poll ``ready`` until it holds, ``proc`` ends or ``seconds`` pass; then the
    process must still be running (its output is shown when it is not)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and proc.poll() is None and not ready():
        time.sleep(0.02)
    assert proc.poll() is None, proc.communicate()


def interrupt(proc: subprocess.Popen, sig: int, timeout: float = 60) -> subprocess.CompletedProcess:
    """Send ``sig`` and wait for the end (killed, and the test failed, after
    ``timeout`` seconds); the result with its standard error."""
    proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, "", err)
