"""Start ``marblevideo live`` in a subprocess and talk to its preview server."""

from __future__ import annotations

import json
import subprocess
import sys
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path

import cv2
import numpy as np
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
    ``url`` is the address of its page (live: with --preview); ``preexec`` runs in
    the child before it starts (a resource limit)."""

    def __init__(
        self, *args, cwd: Path, preview: bool = True, timeout: float = 60.0, command="live",
        preexec=None,
    ):  # fmt: skip
        cmd = [sys.executable, "-m", "marblevideo", command, *map(str, args)]
        env = subprocess_env(PYTHONUNBUFFERED="1")
        self.stderr_path = cwd / f"{command}.stderr"
        self.stderr_file = self.stderr_path.open("w")
        self.proc = subprocess.Popen(
            cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=self.stderr_file, text=True,
            preexec_fn=preexec,
        )  # fmt: skip
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
        """The answer's body (JSON decoded); a first render may build its program on
        a cold cache, so it is given a minute, as :meth:`post` is given 30 s."""
        with urllib.request.urlopen(self.url.rstrip("/") + path, timeout=60) as r:
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


@contextmanager
def designer_page(browser, folder: Path, *args: object, duration: float = 60):
    """``marblevideo design ARGS --no-browser --port 0`` run in ``folder`` for at
    most ``duration`` s, and its page once ready: yields (page, errors) (the
    page's errors, for the caller to check); the page is closed after, and the
    designer must then exit with status 0."""
    app = LiveProcess(
        *args, "--no-browser", "--port", "0", "--duration", duration, cwd=folder, command="design"
    )
    try:
        page, errors = watched_page(browser, app.url, "body[data-ready='1']")
        yield page, errors
        page.close()
    finally:
        assert app.stop() == 0


@contextmanager
def live_designer(browser, folder: Path, recipe: dict):
    """``marblevideo live samples/coffee.jpg --loop --preview`` (600x400, the clock
    running) on ``recipe`` saved as ``folder``/live.json, and the page in live mode: yields
    (live, page, errors, saved), ``saved()`` the file's ops now; the session
    must then exit with status 0."""
    from helpers import ROOT

    path = folder / "live.json"
    path.write_text(json.dumps(recipe))
    live = LiveProcess(
        ROOT / "samples" / "coffee.jpg", "--loop", "--ops", path, "--preview", "--port", "0",
        "--duration", "120", cwd=folder,
    )  # fmt: skip
    try:
        page, errors = watched_page(browser, live.url, "body[data-ready='1'][data-mode='live']")
        yield live, page, errors, lambda: json.loads(path.read_text())["ops"]
    finally:
        assert live.stop() == 0, live.stderr()


# The page, driven in Chromium: waits, drags and what the sheet shows.

INK = "#1d3557"  # the page's first colour


REFUSED = "Failed to load resource: the server responded with a status of 400 (Bad Request)"


def wait_for(pred, what: str, timeout: float = 20.0):
    """Poll ``pred`` until it gives a true value (returned); fail with ``what``
    after ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while not (value := pred()):
        assert time.monotonic() < end, what
        time.sleep(0.05)
    return value


def pixel(page, x: float, y: float) -> str:
    """The sheet's colour at frame pixel (x, y) of the unzoomed sheet (whose canvas
    has the sheet's device pixels, the frame scaled), as #rrggbb."""
    return page.evaluate(
        """([x, y]) => {
            const sheet = document.getElementById('sheet'), [fw, fh] = designer.state.info.size;
            const px = Math.floor(x * sheet.width / fw), py = Math.floor(y * sheet.height / fh);
            const d = sheet.getContext('2d').getImageData(px, py, 1, 1).data;
            return '#' + [d[0], d[1], d[2]].map((c) => c.toString(16).padStart(2, '0')).join('');
        }""",
        [x, y],
    )


def settled(page, frames: int, shown: str = "all", ops: list | None = None) -> None:
    """Wait until the sheet shows an exact frame newer than ``frames`` of the saved
    recipe (of the ops ``shown``), and with ``ops``, once the page holds those ops."""
    page.wait_for_function(
        """([n, shown, ops]) => {
            const d = document.getElementById('sheet').dataset;
            return Number(d.frames) > n && d.draft === '0' && d.shown === shown
                && d.version === String(designer.state.version)
                && (ops === null || JSON.stringify(designer.state.doc.ops) === JSON.stringify(ops));
        }""",
        arg=[frames, shown, ops],
    )


def drag(page, client, a, b) -> str:
    """Drag the mouse from frame pixel ``a`` to ``b`` in eight moves; the number the
    page showed beside the hand just before it let go."""
    page.mouse.move(*client(*a))
    page.mouse.down()
    for k in range(1, 9):
        page.mouse.move(*client(a[0] + (b[0] - a[0]) * k / 8, a[1] + (b[1] - a[1]) * k / 8))
        time.sleep(0.03)
    label = page.get_attribute("#overlay", "data-label")
    page.mouse.up()
    return label


def frames(page) -> int:
    return int(page.evaluate("document.getElementById('sheet').dataset.frames || 0"))


def shot(page) -> np.ndarray:
    png = page.locator("#sheet").screenshot()
    return cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR).astype(np.int16)


def frame_diff(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).mean())


def live_settled(page, live) -> np.ndarray:
    """The sheet once it shows a frame rendered after now (three JPEGs on)."""
    seq = live.get("/stats")["jpeg_seq"]
    page.wait_for_function(
        f"Number(document.getElementById('sheet').dataset.seq) >= {seq + 3}", timeout=20000
    )
    return shot(page)
