"""The designer's HTTP API: described as OpenAPI (``GET /api/openapi.json``, one
table in marblevideo.design.routes that the session also answers from) and
fuzzed with schemathesis against a real ``marblevideo design`` on loopback
(tests/support/api_fuzz.py: never a 5xx, never a hang, a 4xx in one JSON line).
Derandomized (conftest's ``ci`` profile), so a failure replays."""

from __future__ import annotations

import json
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from api_fuzz import TIMEOUT, api_cases, check_answer, designer
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from marblevideo.design.routes import ROUTES, TABLE, openapi

pytestmark = pytest.mark.tier("integration")


@pytest.fixture(scope="module")
def url(tmp_path_factory):
    with designer(tmp_path_factory.mktemp("api"), seconds=86400) as base:  # a campaign's hours
        yield base


def test_the_description_is_the_table(url):
    with urllib.request.urlopen(f"{url}api/openapi.json", timeout=30) as r:
        served = json.loads(r.read())
    assert served == openapi()
    assert served["openapi"].startswith("3.")
    described = {(m.upper(), p) for p, ops in served["paths"].items() for m in ops}
    assert described == {(r.method, r.path) for r in ROUTES}
    assert {r for r in ROUTES if r.call is None} == {ROUTES[0], ROUTES[1]}  # the server's own
    assert ("GET", "/api/openapi.json") in TABLE


@pytest.fixture(scope="module")
def cases(url):
    return api_cases(url)


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_every_answer_is_well_formed(url, cases, data):
    check_answer(url, data.draw(cases, label="request"))


CORPUS = Path(__file__).resolve().parent / "data" / "fuzz"


def _send(url: str, step: dict) -> tuple[int, dict | None]:
    body = None if "body" not in step else json.dumps(step["body"]).encode()
    request = urllib.request.Request(
        url.rstrip("/") + step["path"], data=body, method=step["method"],
        headers={"Content-Type": "application/json"},
    )  # fmt: skip
    try:
        with urllib.request.urlopen(request, timeout=TIMEOUT) as r:
            return r.status, None
    except urllib.error.HTTPError as exc:
        return exc.code, json.loads(exc.read())


@pytest.mark.parametrize("path", sorted(CORPUS.glob("*.http")), ids=lambda p: p.name)
def test_the_corpus_requests_replay(tmp_path, path):
    """Each once a finding (a 5xx, a runaway, a designer left broken), in order on a
    fresh designer: the status, and the one-line error where one is given."""
    with designer(tmp_path, seconds=120) as base:
        for step in json.loads(path.read_text()):
            code, answer = _send(base, step)
            assert code == step["status"], (step, answer)
            if "error" in step:
                assert step["error"] in answer["error"] and "\n" not in answer["error"]
