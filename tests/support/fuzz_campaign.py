"""A pytest plugin for ``python -m benchmarks fuzz`` (``-p fuzz_campaign``): each
Hypothesis test collected runs for MARBLEVIDEO_FUZZ_SECONDS with a fresh seed
(not derandomized), no example database and no limit on examples, under the limits
its own test sets (each input bounded in memory and time as in CI). Its inputs,
seconds and findings (the first line of each distinct failure, as found, before
any shrinking) go to MARBLEVIDEO_FUZZ_REPORT as JSON by test id."""

from __future__ import annotations

import json
import os
import time

import pytest
from hypothesis import settings

SECONDS = float(os.environ.get("MARBLEVIDEO_FUZZ_SECONDS", "60"))
REPORT = os.environ.get("MARBLEVIDEO_FUZZ_REPORT")
STATS: dict[str, dict] = {}
STOPPED: list[str] = []  # the tests whose time ran out


class Stop(BaseException):
    """The test's time is up (a BaseException: Hypothesis and the code under test let it by)."""


def _counted(nodeid: str, inner, fixtures):
    stats = STATS[nodeid] = {"inputs": 0, "seconds": 0.0, "findings": []}
    start: list[float] = []

    def run(*args, **kwargs):
        now = time.monotonic()
        start or start.append(now)
        stats["seconds"] = round(now - start[0], 1)
        if now - start[0] > SECONDS:
            STOPPED.append(nodeid)
            raise Stop
        stats["inputs"] += 1
        try:
            return inner(*args, **kwargs)
        except Exception as exc:
            if type(exc).__module__.startswith("hypothesis"):  # its control flow: reject()
                raise
            given = ", ".join(f"{k}={v!r}" for k, v in kwargs.items() if k not in fixtures)
            line = f"{type(exc).__name__}: {exc}".splitlines()[0][:1500]
            line += f" ({given[:200]})" if given else ""
            if line not in stats["findings"]:
                stats["findings"].append(line)
            raise

    return run


def pytest_collection_modifyitems(items):
    for item in items:
        handle = getattr(item.obj, "hypothesis", None)
        if handle is None:
            continue
        fixtures = {*item.fixturenames, "data"}  # what Hypothesis did not draw (data: its draws)
        handle.inner_test = _counted(item.nodeid, handle.inner_test, fixtures)
        own = getattr(item.obj, "_hypothesis_internal_use_settings", settings())
        item.obj._hypothesis_internal_use_settings = settings(
            own, max_examples=10**9, derandomize=False, database=None, deadline=None
        )


@pytest.hookimpl(wrapper=True)
def pytest_pyfunc_call(pyfuncitem):
    try:
        return (yield)
    except BaseException:
        # time up: the Stop as it is, or what Hypothesis made of it (a replay it
        # could not finish); the findings before it are in STATS
        if pyfuncitem.nodeid in STOPPED:
            return True
        raise


def pytest_sessionfinish(session):
    if REPORT:
        with open(REPORT, "w") as f:
            json.dump(STATS, f, indent=1)
