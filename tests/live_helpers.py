"""Start ``marblevideo live`` in a subprocess and talk to its preview server."""

from __future__ import annotations

import json
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

from helpers import subprocess_env

# A still-image input with constant (adjustable) and keyframed (animated) parameters.
RECIPE = {
    "marblevideo": 1,
    "antialias": "none",
    "edges": "mirror",
    "ops": [
        {
            "type": "wave",
            "amplitude": {"keys": [{"t": 0, "v": 0}, {"t": 1, "v": 10}]},
            "wavelength": 120,
            "phase": 0,
            "angle": 90,
        },
        {"type": "vortex", "center": [300, 200], "alpha": 200, "lambda": 60},
    ],
}


class LiveProcess:
    """``marblevideo COMMAND ARGS`` running (``live`` by default, or ``design``);
    ``url`` is the address of its page (live: with --preview)."""

    def __init__(
        self, *args, cwd: Path, preview: bool = True, timeout: float = 60.0, command="live"
    ):
        cmd = [sys.executable, "-m", "marblevideo", command, *map(str, args)]
        env = subprocess_env(PYTHONUNBUFFERED="1")
        self.stderr_path = cwd / f"{command}.stderr"
        self.stderr_file = self.stderr_path.open("w")
        self.proc = subprocess.Popen(
            cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=self.stderr_file, text=True
        )
        self.url = None
        if preview:
            line = self.proc.stdout.readline()
            if not line.startswith(("preview: ", "design: ")):
                self.proc.kill()
                raise AssertionError(f"no preview URL: {line!r} {self.stderr()}")
            self.url = line.split(" ", 1)[1].strip()
        self.deadline = time.monotonic() + timeout

    def stderr(self) -> str:
        if not self.stderr_file.closed:
            self.stderr_file.flush()
        return self.stderr_path.read_text()

    def get(self, path: str):
        with urllib.request.urlopen(self.url.rstrip("/") + path, timeout=10) as r:
            body = r.read()
            return json.loads(body) if r.headers.get_content_type() == "application/json" else body

    def post(self, path: str, obj, method: str = "POST") -> dict:
        """``obj`` as JSON; the JSON answer (HTTPError for a status >= 400)."""
        req = urllib.request.Request(
            self.url.rstrip("/") + path,
            data=json.dumps(obj).encode(),
            headers={"Content-Type": "application/json"},
            method=method,
        )
        with urllib.request.urlopen(req, timeout=30) as r:
            return json.loads(r.read())

    def wait_stats(self, pred, timeout: float = 20.0) -> dict:
        end = time.monotonic() + timeout
        while True:
            stats = self.get("/stats")
            if pred(stats):
                return stats
            if time.monotonic() > end:
                raise AssertionError(f"stats never matched: {stats}")
            time.sleep(0.1)

    def stop(self, sig=None, timeout: float = 30.0) -> int:
        import signal

        if self.proc.poll() is None:
            self.proc.send_signal(sig or signal.SIGINT)
        try:
            rc = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait()
        self.proc.stdout.close()
        self.stderr_file.close()
        return rc


def watched_page(browser, url: str, ready: str):
    """(page, errors): a 1300x900 page of ``browser`` at ``url``, once ``ready`` (a
    selector) is there; ``errors`` collects its page errors and console errors."""
    errors: list[str] = []
    page = browser.new_page(viewport={"width": 1300, "height": 900})
    page.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.goto(url)
    page.wait_for_selector(ready)
    return page, errors
