"""The page's web folder served on 127.0.0.1 for headless Chromium with
SwiftShader's WebGL2 (the page's warp): the warp benchmark and its tests;
:func:`serve_folder` serves any folder so (the tests' media over HTTP)."""

from __future__ import annotations

import contextlib
import functools
import http.server
import threading
from pathlib import Path

WEB = Path(__file__).resolve().parents[1] / "marblevideo" / "design" / "web"
ARGS = [
    "--no-sandbox",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--ignore-gpu-blocklist",
]
BLANK = b"<!doctype html><meta charset=utf-8><title>warp</title><body></body>"


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


class _Handler(_Quiet):
    def do_GET(self):  # noqa: N802 (the base class' name)
        if self.path in ("/", "/index.html"):
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.end_headers()
            self.wfile.write(BLANK)
            return
        super().do_GET()

    def guess_type(self, path):
        return "text/javascript" if str(path).endswith(".js") else super().guess_type(path)


def serve_web():
    """The web folder at http://127.0.0.1:PORT/web/ (yields the base URL)."""
    return serve_folder(WEB.parent, _Handler)


@contextlib.contextmanager
def serve_folder(folder, handler_class=_Quiet):
    """``folder``'s files at http://127.0.0.1:PORT/ (yields that base URL), from a
    thread, quietly, until the block ends."""
    handler = functools.partial(handler_class, directory=str(folder))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()
