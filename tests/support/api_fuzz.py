"""The designer's HTTP API fuzzed with schemathesis from its own description
(``GET /api/openapi.json``, :mod:`marblevideo.design.routes`) against a real
``marblevideo design`` on loopback: requests that fit the description and
requests that do not (schemathesis's positive and negative modes). The property:
every answer is a well-formed HTTP answer within :data:`TIMEOUT` seconds, never
a 5xx; a 4xx's body is JSON whose ``error`` is one line; the status and content
type are ones the description gives. Shared by tests/test_api_fuzz.py and
``python -m benchmarks fuzz``."""

from __future__ import annotations

import json
import resource
import urllib.request
from contextlib import contextmanager
from pathlib import Path

import schemathesis
from hypothesis import strategies as st
from live_helpers import LiveProcess
from schemathesis import GenerationMode
from schemathesis.specs.openapi.checks import content_type_conformance, status_code_conformance

#: Seconds an answer may take (a render of a frame at the largest size
#: included): more is a hang.
TIMEOUT = 30
#: The server's address space (RLIMIT_AS): a runaway fails there, not in the machine's memory.
SERVER_AS = 16 << 30
#: What the fuzzed designer edits: a small sheet, so renders stay quick.
RECIPE = {
    "marblevideo": 1,
    "canvas": [64, 48],
    "antialias": "none",
    "ops": [{"type": "drop", "center": [32, 24], "radius": 9, "color": "#2255aa"}],
}


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (SERVER_AS, SERVER_AS))


@contextmanager
def designer(folder: Path, seconds: float = 600):
    """``marblevideo design`` on a small recipe in ``folder`` (under SERVER_AS):
    yields its base URL; it must then exit with status 0."""
    path = folder / "api.json"
    path.write_text(json.dumps(RECIPE))
    app = LiveProcess(
        "--ops", path, "--no-browser", "--port", "0", "--duration", seconds, cwd=folder,
        command="design", preexec=_limited,
    )  # fmt: skip
    try:
        yield app.url
        assert app.proc.poll() is None, f"the designer died: {app.stderr()}"
    finally:
        assert app.stop() == 0, app.stderr()


def api_cases(url: str):
    """A strategy of requests (schemathesis Cases) for every route the designer
    at ``url`` describes, fitting the description or not."""
    schema = schemathesis.openapi.from_url(f"{url}api/openapi.json")
    modes = (GenerationMode.POSITIVE, GenerationMode.NEGATIVE)
    return st.one_of(*(schema.as_strategy(generation_mode=m) for m in modes))


def check_answer(url: str, case) -> int:
    """Send ``case`` to the designer at ``url`` and check the property; its status."""
    response = case.call(base_url=url.rstrip("/"), timeout=TIMEOUT)
    code, what = response.status_code, case.as_curl_command()
    if code >= 500:  # the saved recipe too: a route's answer depends on it
        with urllib.request.urlopen(f"{url}api/recipe", timeout=TIMEOUT) as r:
            saved = json.dumps(json.loads(r.read()))[:4000]
        raise AssertionError(f"{what}: {code} {response.text[:300]} over {saved}")
    if code >= 400:
        ctype = response.headers.get("content-type", [None])[0]  # lower-case keys, lists
        assert ctype == "application/json", (what, code, ctype, response.text[:200])
        error = json.loads(response.content)["error"]
        assert isinstance(error, str) and error and "\n" not in error, (what, error)
    checks = [status_code_conformance, content_type_conformance]
    case.validate_response(response, checks=checks)
    return code
