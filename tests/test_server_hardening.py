"""A hostile HTTP client against both servers:
``marblevideo design`` (a real subprocess) and ``marblevideo live --preview``
(the live session and its preview server in this process, as tests/test_live.py
runs them), each on a real recipe file.

- A body nested 100000 levels deep is the client's fault: 400 in one line,
  nothing saved, the server still answering.
- A write (PUT, POST) from another origin is refused (403) on every writing
  route; the page's own origin and scripts that send no Origin are served.
- While the file on disk is broken, ``GET /api/recipe`` says so (409, the error
  with its JSON path, the last good recipe as ``last_good``).
- ``/stats`` is read while the session's threads count frames.
"""

from __future__ import annotations

import http.client
import json
import threading
import time

import pytest
from live_helpers import RECIPE, LiveProcess

from marblevideo.design.live import LiveDesign
from marblevideo.limits import MAX_DEPTH
from marblevideo.live.session import LiveSession
from marblevideo.live.sources import TestPattern
from marblevideo.serve.server import Server, json_depth

pytestmark = pytest.mark.tier("fast")

DROP = {"type": "drop", "center": [40, 30], "radius": 12, "color": "#1d3557"}
DESIGN = {"marblevideo": 1, "canvas": [96, 64], "antialias": "none", "ops": [DROP]}
BROKEN = {**DESIGN, "ops": [{**DROP, "radius": 0}]}


class Client:
    """Raw requests to a server on 127.0.0.1:``port``: (status, body) answers."""

    def __init__(self, port: int):
        self.port = port
        self.host = f"127.0.0.1:{port}"

    def send(self, method: str, path: str, body: bytes | None = None, **headers):
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        headers = {"Content-Type": "application/json", **headers}
        conn.request(method, path, body=body, headers=headers)
        r = conn.getresponse()
        answer = r.status, r.read()
        conn.close()
        return answer

    def json(self, method: str, path: str, obj=None, **headers) -> tuple[int, dict]:
        data = None if obj is None else json.dumps(obj).encode()
        status, body = self.send(method, path, data, **headers)
        return status, json.loads(body)


@pytest.fixture(scope="module")
def designer(tmp_path_factory):
    """``marblevideo design`` on a 96x64 sheet: (its Client, its FILE)."""
    folder = tmp_path_factory.mktemp("design")
    path = folder / "r.json"
    path.write_text(json.dumps(DESIGN))
    app = LiveProcess(
        "--ops", path, "--no-browser", "--port", "0", "--duration", "300",
        cwd=folder, command="design",
    )  # fmt: skip
    port = int(app.url.rstrip("/").rsplit(":", 1)[1])
    yield Client(port), path
    assert app.stop() == 0
    assert "Traceback" not in app.stderr(), app.stderr()


@pytest.fixture
def live(tmp_path, renderer):
    """``live --preview``'s server (the designer's page in live mode) over a test
    pattern: (its Client, its recipe file, the session)."""
    path = tmp_path / "live.json"
    path.write_text(json.dumps(RECIPE))
    session = LiveSession(path, TestPattern((96, 64), 30), renderer=renderer, jpeg=True, quiet=True)
    server = Server(LiveDesign(session), 0)
    server.start()
    try:
        yield Client(server.address[1]), path, session
    finally:
        server.stop()
        session.close()


def test_the_designer_has_no_live_routes(designer):
    """One server for both modes: a live session's routes (its counters, frames and
    clock) are not found on the designer's, rather than a traceback on its stderr
    (the fixture's teardown checks there is none)."""
    client, _ = designer
    for method, route in (("GET", "/stats"), ("GET", "/frame.jpg"), ("GET", "/stream.mjpg"),
                          ("POST", "/control"), ("GET", "/params")):  # fmt: skip
        assert client.send(method, route, b"{}" if method == "POST" else None)[0] == 404, route
    assert client.json("GET", "/api/info")[1]["mode"] == "design"


def test_json_depth_is_counted_without_parsing():
    assert [json_depth(t) for t in (b"1", b"[]", b"[[{}], {}]", b"")] == [0, 1, 3, 0]
    assert json_depth(json.dumps({"a": "[[[{{{", "b": ['\\"[[[', []]}).encode()) == 3
    assert json_depth(b"[" * 100000) == 100000
    assert json_depth(b'["an unterminated string [[[') == 1  # the parser refuses it
    assert json_depth(b'"\\' * 500000) == 0  # linear, however the quotes fall


# ---------------------------------------------------------------- item 2: deep nesting


def refused_in_one_line(status: int, body: bytes, code: int) -> str:
    assert status == code, body
    error = json.loads(body)["error"]
    assert "\n" not in error and error
    return error


def test_deep_json_is_a_bad_request_to_the_designer(designer):
    client, path = designer
    before = path.read_bytes()
    deep = b"[" * 100000 + b"]" * 100000
    for method, route in (("PUT", "/api/recipe"), ("POST", "/api/frame.rgba")):
        for body in (deep, b"[" * 100000, b"[" * (MAX_DEPTH + 1)):
            error = refused_in_one_line(*client.send(method, route, body), 400)
            assert "nested too deeply" in error
    # the deepest a body may be still parses (and is refused as a recipe)
    error = refused_in_one_line(*client.send("PUT", "/api/recipe", b"[" * MAX_DEPTH), 400)
    assert "invalid JSON" in error
    assert path.read_bytes() == before
    status, info = client.json("GET", "/api/info")
    assert status == 200 and info["error"] is None and info["ops"] == 1


def test_deep_json_is_a_bad_request_to_the_live_server(live):
    client, path, session = live
    before = path.read_bytes()
    for method, route in (("PUT", "/api/recipe"), ("POST", "/api/learn"),
                          ("POST", "/control")):  # fmt: skip
        levels = 60000 if route == "/control" else 100000  # /control takes 64 KiB at most
        status, body = client.send(method, route, b"[" * levels)
        assert "nested too deeply" in refused_in_one_line(status, body, 400)
    # a Content-Length that is no byte count is the client's fault too
    for length in ("-5", "abc", "1e3", "\u00b2"):
        status, body = client.send("PUT", "/api/recipe", None, **{"Content-Length": length})
        assert "Content-Length" in refused_in_one_line(status, body, 400)
    assert path.read_bytes() == before and session.recipe_version == 1
    assert client.json("GET", "/stats")[0] == 200


# ---------------------------------------------------------------- item 3: cross-origin writes


def writes(client: Client, origin_headers: dict, routes) -> list[int]:
    return [client.send(m, r, json.dumps(b).encode(), **origin_headers)[0] for m, r, b in routes]


def check_origins(client: Client, routes, path) -> None:
    """Every writing route refuses other origins (403, one line, nothing saved)
    and serves its own origin and scripts without Origin."""
    before = path.read_bytes()
    for hostile in (
        {"Origin": "http://evil.example"},
        {"Origin": "null"},  # a sandboxed frame, a file:// page
        {"Origin": f"http://localhost:{client.port}"},  # another origin than the Host named
        {"Origin": f"https://{client.host}"},
        {"Referer": "http://evil.example/attack.html"},
    ):
        for method, route, body in routes:
            status, answer = client.send(method, route, json.dumps(body).encode(), **hostile)
            error = refused_in_one_line(status, answer, 403)
            assert f"{method} {route.partition('?')[0]}: cross-origin" in error, error
    assert path.read_bytes() == before
    own = f"http://{client.host}"
    assert writes(client, {"Origin": own}, routes) == [200] * len(routes)
    assert writes(client, {"Referer": own + "/"}, routes) == [200] * len(routes)
    assert writes(client, {}, routes) == [200] * len(routes)
    # localhost is the server's origin too when the page was opened by that name
    localhost = {"Host": f"localhost:{client.port}", "Origin": f"http://localhost:{client.port}"}
    assert writes(client, localhost, routes) == [200] * len(routes)


def test_cross_origin_writes_to_the_designer_are_refused(designer):
    client, path = designer
    routes = [
        ("PUT", "/api/recipe", DESIGN),
        ("POST", "/api/frame.png?w=32", DESIGN),
        ("POST", "/api/frame.rgba?draft=1", DESIGN),
    ]
    check_origins(client, routes, path)
    assert json.loads(path.read_text()) == DESIGN


def test_cross_origin_writes_to_the_live_server_are_refused(live):
    client, path, session = live
    routes = [
        ("PUT", "/api/recipe", RECIPE),
        ("POST", "/api/learn", {}),
        ("POST", "/control", {"paused": True}),
    ]
    check_origins(client, routes, path)
    assert session.clock.paused
    # reads are not writes: the page and a script read as before, whatever the Origin
    assert client.json("GET", "/stats", Origin="http://evil.example")[0] == 200


# ---------------------------------------------------------------- item 9: a broken file on disk


def wait_error(client: Client, timeout: float = 10.0) -> dict:
    end = time.monotonic() + timeout
    while (info := client.json("GET", "/api/info")[1])["error"] is None:
        assert time.monotonic() < end, info
        time.sleep(0.1)
    return info


def check_broken(client: Client, path, good: dict, broken: dict) -> None:
    """FILE saved invalid by another program: GET /api/recipe is 409 with the
    error (its JSON path) and the last good recipe; a good PUT makes it 200."""
    assert client.json("GET", "/api/recipe") == (200, good)
    path.write_text(json.dumps(broken))
    info = wait_error(client)
    status, answer = client.json("GET", "/api/recipe")
    assert status == 409
    assert (
        answer["error"]
        == info["error"]
        == (f"{path}: ops[0].radius: must be > 0, got 0 (keeping the previous recipe)")
    )
    assert answer["last_good"] == good and answer["version"] == info["version"]
    assert client.json("PUT", "/api/recipe", good)[0] == 200
    assert client.json("GET", "/api/recipe") == (200, good)


def test_the_designer_says_its_file_is_broken(designer):
    client, path = designer
    check_broken(client, path, DESIGN, BROKEN)


def test_the_live_server_says_its_file_is_broken(live):
    client, path, session = live
    broken = {**RECIPE, "ops": [{**DROP, "radius": 0}]}
    path.write_text(json.dumps(broken))
    session.check_reload()  # what the session's watcher does every 0.5 s
    status, answer = client.json("GET", "/api/recipe")
    assert status == 409 and answer["last_good"] == RECIPE
    assert answer["error"] == (
        f"{path}: ops[0].radius: must be > 0, got 0 (keeping the previous recipe)"
    )
    assert client.json("PUT", "/api/recipe", RECIPE)[0] == 200
    assert client.json("GET", "/api/recipe") == (200, RECIPE)


def test_stats_are_read_while_frames_are_counted():
    """``/stats`` reads the session's rate windows while the render and JPEG threads
    add to them (the soak benchmark met 'deque mutated during iteration')."""
    from marblevideo.live.meters import RateWindow

    window, stop, errors = RateWindow(), threading.Event(), []

    def count() -> None:
        while not stop.is_set():
            window.add(time.monotonic(), 0.01)

    adder = threading.Thread(target=count)
    adder.start()
    try:
        end = time.monotonic() + 1.5
        while time.monotonic() < end:
            window.rate(time.monotonic()), window.median(), window.quantile(0.95)
    except RuntimeError as exc:
        errors.append(exc)
    finally:
        stop.set()
        adder.join()
    assert errors == [] and window.rate(time.monotonic()) > 0
