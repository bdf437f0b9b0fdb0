"""The HTTP server of ``marblevideo design`` and ``marblevideo live --preview``:
127.0.0.1 only, standard library, one session behind it.

Routes:

- ``GET /``: the session's page, when it has one (``page()``): the designer's
  (:mod:`marblevideo.design`; for ``live --preview``, in live mode).
- ``GET /stream.mjpg``: the marbled frames as MJPEG (``multipart/x-mixed-replace``),
  each JPEG sent once, newest first: a slow client skips frames, it never queues them.
- ``GET /frame.jpg``: the newest JPEG; ``?after=SEQ``: one newer than SEQ, waited
  for up to 2 s (none by then: 204 No Content, to be asked again). The
  sequence number comes as the ``X-Frame-Seq`` header, and the serial of the
  designer's preview it shows, if any, as ``X-Preview-Serial``, and the
  animation clock's time it was marbled at as ``X-Frame-Time``, seconds.
- ``GET /web/NAME``: the page's static files (its ES modules), from the
  session's ``web`` folder when it has one (:func:`static_file`).
- ``GET /stats``: JSON counters (fps, latency, dropped frames, recipe version and
  error, the clock's state); the page polls it.
- ``POST /control``: a JSON object (see :meth:`LiveSession.control`), applied from
  the next frame; answers the new state, or 400 with ``{"error": ...}``.

A session with an ``api(method, path, query, body)`` method (the designer's,
:mod:`marblevideo.design`) answers every ``/api/...`` request itself, and one
with a ``page()`` method gives the page. The live routes are a live session's
(``stats()``, ``latest_jpeg()``, ``control()``): 404 for a session without them
(the designer's, :class:`~marblevideo.design.session.DesignSession`).

Every error is answered as JSON, ``{"error": "..."}`` in one line (the
designer's routes are described at ``GET /api/openapi.json``:
:mod:`marblevideo.design.routes`). Requests must name the server as their Host
(127.0.0.1 or localhost), and
``/control`` and the API's PUT and POST take ``Content-Type: application/json``
only, so other web pages open in the same browser cannot drive it (no CORS
headers are ever sent). A PUT or POST that says where it comes from (its
``Origin``, else its ``Referer``) must come from the server's own origin
(``http://`` and the Host it named): 403 otherwise; scripts that send neither
are served. A JSON body nested deeper than
:data:`~marblevideo.limits.MAX_DEPTH` levels is refused (400) before it is
parsed.
"""

from __future__ import annotations

import json
import re
import sys
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import parse_qs, urlsplit

import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.limits import DEFAULT_PORT, MAX_DEPTH

BOUNDARY = "marblevideoframe"
#: Largest request body, in bytes (a recipe PUT to the designer's API).
MAX_BODY = 4 << 20
HOST = "127.0.0.1"
#: A JSON string literal (its escapes included), whose brackets are no nesting;
#: one left open runs to the end (so the scan stays linear in the text's length).
_STRING = re.compile(rb'"(?:[^"\\]++|\\.)*+(?:"|\\?\Z)', re.DOTALL)
#: The page's static files: their types by suffix, and the names served (one
#: plain name in the folder: no subfolders, no "..", no hidden files).
MIME = {
    ".js": "text/javascript; charset=utf-8",
    ".html": "text/html; charset=utf-8",
    ".css": "text/css; charset=utf-8",
}
_STATIC = re.compile(r"/web/[a-z][a-z0-9_-]*(\.[a-z]+)")


def static_file(folder, path: str) -> tuple[bytes, str] | None:
    """``GET /web/NAME``: the file NAME of ``folder`` (a directory as a Path or an
    importlib resource) and its Content-Type; None when ``path`` is not such a
    file of a known type (or there is no folder)."""
    match = _STATIC.fullmatch(path)
    if folder is None or match is None or match[1] not in MIME:
        return None
    found = folder / path.removeprefix("/web/")
    return (found.read_bytes(), MIME[match[1]]) if found.is_file() else None


def json_depth(data: bytes) -> int:
    """How deeply the JSON text ``data`` nests lists and objects (0: a scalar),
    counted without parsing it: brackets inside strings are skipped; an
    unbalanced or invalid text gets a depth all the same (the parser refuses it)."""
    text = np.frombuffer(_STRING.sub(b'""', data), np.uint8)
    opens = (text == ord("[")) | (text == ord("{"))
    closes = (text == ord("]")) | (text == ord("}"))
    steps = opens.astype(np.int32) - closes
    return int(np.cumsum(steps).max(initial=0))


def request_json(body: bytes | None):
    """A request's JSON body; ValueError, in one line, when it is not JSON (a
    recursion too deep for the parser included)."""
    try:
        return json.loads(body or b"null")
    except (ValueError, RecursionError) as exc:
        raise ValueError(f"request body: invalid JSON: {exc}") from None


def json_answer(obj, code: int = 200) -> tuple[int, bytes, str]:
    """``obj`` as a session's answer to an API request: (status, body, content type)."""
    return code, json.dumps(obj).encode(), "application/json"


class _Handler(BaseHTTPRequestHandler):
    server: _HTTPD
    protocol_version = "HTTP/1.1"
    # an answer's body follows its headers at once (with Nagle's algorithm it waits
    # for the client's delayed ACK of the headers: ~40 ms a request on Linux)
    disable_nagle_algorithm = True

    def log_message(self, format, *args):  # noqa: A002 - quiet: the terminal is for errors
        pass

    def _host_ok(self) -> bool:
        port = self.server.server_address[1]
        allowed = {f"{HOST}:{port}", f"localhost:{port}"}
        if self.headers.get("Host", "") in allowed:
            return True
        self._json({"error": f"Host {self.headers.get('Host', '')!r} is not this server"}, 403)
        return False

    def _origin_ok(self) -> bool:
        """A write (PUT, POST) from the server's own page or from a script that
        says no origin: its Origin header, else its Referer's origin, must be
        ``http://HOST`` of the (already checked) Host header; 403 otherwise."""
        origin = self.headers.get("Origin")
        if origin is None and self.headers.get("Referer"):
            parts = urlsplit(self.headers["Referer"])
            origin = f"{parts.scheme}://{parts.netloc}"
        if origin is None or origin == f"http://{self.headers['Host']}":
            return True
        route = f"{self.command} {self.path.partition('?')[0]}"
        self._json({"error": f"{route}: cross-origin request from {origin} refused"}, 403)
        self.close_connection = True  # its body is left unread
        return False

    def _send(self, code: int, body: bytes, ctype: str) -> None:
        self.send_response(code)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)

    def _json(self, obj, code: int = 200) -> None:
        self._send(code, json.dumps(obj).encode(), "application/json")

    def _not_found(self) -> None:
        self._json({"error": f"{self.command} {self.path.partition('?')[0]!r}: not found"}, 404)

    def _api(self, method: str) -> bool:
        """Hand an ``/api/`` request to the session; whether it was one."""
        session = self.server.session
        path, _, query = self.path.partition("?")
        if not path.startswith("/api/") or not hasattr(session, "api"):
            return False
        body = None
        if method in ("PUT", "POST"):
            body = self._body("api")
            if body is None:
                return True
        self._send(*session.api(method, path, query, body))
        return True

    def _body(self, what: str, limit: int = MAX_BODY) -> bytes | None:
        """The JSON request body, or None once a 415 or 413 is sent."""
        ctype = self.headers.get("Content-Type", "").split(";")[0].strip()
        if ctype != "application/json":
            self._json({"error": f"{what}: Content-Type must be application/json"}, 415)
            self.close_connection = True  # its body is left unread
            return None
        length = self.headers.get("Content-Length") or "0"
        if not (length.isascii() and length.isdigit()):
            self._json({"error": f"{what}: Content-Length must be a byte count"}, 400)
            self.close_connection = True
            return None
        length = int(length)
        if length > limit:
            self._json({"error": f"{what}: request too large"}, 413)
            self.close_connection = True
            return None
        body = self.rfile.read(length)
        if json_depth(body) > MAX_DEPTH:
            message = f"{what}: request body nested too deeply (more than {MAX_DEPTH} levels)"
            self._json({"error": message}, 400)
            return None
        return body

    def do_GET(self):  # noqa: N802 - http.server's naming
        if not self._host_ok() or self._api("GET"):
            return
        session = self.server.session
        path, _, query = self.path.partition("?")
        if path == "/" and hasattr(session, "page"):
            self._send(200, session.page(), "text/html; charset=utf-8")
        elif (found := static_file(getattr(session, "web", None), path)) is not None:
            self._send(200, *found)
        elif path == "/stats" and hasattr(session, "stats"):
            self._json(session.stats())
        elif path == "/frame.jpg" and hasattr(session, "latest_jpeg"):
            self._frame(query)
        elif path == "/stream.mjpg" and hasattr(session, "latest_jpeg"):
            self._stream()
        else:
            self._not_found()

    def _frame(self, query: str) -> None:
        """The newest JPEG; with ``after=SEQ``, one newer than SEQ (waited for up to
        2 s: 204 No Content, X-Frame-Seq SEQ, when none came: a designed answer, ask
        again; not an error a browser would log). Its sequence number is the
        X-Frame-Seq header."""
        try:
            after = int(parse_qs(query).get("after", ["0"])[-1])
        except ValueError:
            self._json({"error": "after: expected a frame number"}, 400)
            return
        seq, data, serial, shown = self.server.session.latest_jpeg(after, timeout=2.0)
        if data is None:
            self.send_response(204)
            self.send_header("Cache-Control", "no-store")
            self.send_header("X-Frame-Seq", str(seq))
            self.end_headers()
            return
        self.send_response(200)
        self.send_header("Content-Type", "image/jpeg")
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Frame-Seq", str(seq))
        if serial:
            self.send_header("X-Preview-Serial", str(serial))
        if shown is not None:
            self.send_header("X-Frame-Time", repr(float(shown)))
        self.end_headers()
        self.wfile.write(data)

    def _stream(self) -> None:
        session = self.server.session
        self.send_response(200)
        self.send_header("Content-Type", f"multipart/x-mixed-replace; boundary={BOUNDARY}")
        self.send_header("Cache-Control", "no-store")
        self.send_header("Connection", "close")
        self.end_headers()
        self.close_connection = True
        seq = 0
        try:
            while not self.server.closing.is_set():
                seq, data, *_ = session.latest_jpeg(seq, timeout=0.5)
                if data is None:
                    continue
                head = (
                    f"--{BOUNDARY}\r\nContent-Type: image/jpeg\r\n"
                    f"Content-Length: {len(data)}\r\n\r\n"
                ).encode()
                self.wfile.write(head + data + b"\r\n")
                self.wfile.flush()
        except (BrokenPipeError, ConnectionResetError, TimeoutError):
            pass

    def do_PUT(self):  # noqa: N802 - http.server's naming
        if self._host_ok() and self._origin_ok() and not self._api("PUT"):
            self._not_found()

    def do_POST(self):  # noqa: N802 - http.server's naming
        if not (self._host_ok() and self._origin_ok()) or self._api("POST"):
            return
        if self.path != "/control" or not hasattr(self.server.session, "control"):
            self._not_found()
            return
        body = self._body("control", 65536)
        if body is None:
            return
        try:
            request = json.loads(body or b"null")
            self._json(self.server.session.control(request))
        except (ValueError, RecursionError, UsageError) as exc:
            self._json({"error": str(exc)}, 400)


class _HTTPD(ThreadingHTTPServer):
    daemon_threads = True
    allow_reuse_address = True

    def handle_error(self, request, client_address):
        """A client gone mid-answer (a closed page) is no error; others are printed."""
        if not isinstance(sys.exc_info()[1], BrokenPipeError | ConnectionResetError):
            super().handle_error(request, client_address)

    def __init__(self, address, session):
        self.session = session
        self.closing = threading.Event()
        super().__init__(address, _Handler)


class Server:
    """Serves ``session`` (a design or live session) on 127.0.0.1:``port`` (0: any
    free port) in a thread."""

    def __init__(self, session, port: int = DEFAULT_PORT):
        try:
            self.httpd = _HTTPD((HOST, port), session)
        except OSError as exc:
            raise MediaError(f"preview: cannot listen on {HOST}:{port}: {exc.strerror}") from None
        self._thread: threading.Thread | None = None

    @property
    def address(self) -> tuple[str, int]:
        return self.httpd.socket.getsockname()[:2]

    @property
    def url(self) -> str:
        host, port = self.address
        return f"http://{host}:{port}/"

    def start(self) -> None:
        self._thread = threading.Thread(
            target=self.httpd.serve_forever, kwargs={"poll_interval": 0.2}, daemon=True
        )
        self._thread.start()

    def stop(self) -> None:
        self.httpd.closing.set()
        if self._thread is not None:
            self.httpd.shutdown()
            self._thread.join(5.0)
        self.httpd.server_close()
