"""`marblevideo devices --check`: the device self-test, on the real device (PoCL
here) against the real NumPy reference; nothing mocked."""

from __future__ import annotations

import io
import os
from dataclasses import replace

import pytest

from marblevideo.opencl import selfcheck
from marblevideo.opencl.device import choose_device
from marblevideo.opencl.program import UNROLL_LIMIT
from marblevideo.ops import REGISTRY
from marblevideo.recipe.antialias import PATTERNS
from marblevideo.recipe.frame import EDGE_MODES
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("integration")

DEVICE = os.environ.get("MARBLEVIDEO_TEST_DEVICE")


def shifted(spec, geom, image):
    """The real reference with the picture moved by one output pixel to the left:
    what a device that misplaces every sample by one pixel would render."""
    kx, ky, tx, ty = geom.to_canvas
    return reference_render(spec, replace(geom, to_canvas=(kx, ky, tx + kx, ty)), image)


@pytest.fixture(scope="module")
def report():
    return selfcheck.check_device(DEVICE)


def test_cli_check_passes_and_names_the_device(cli):
    info = choose_device(DEVICE)
    proc = cli("devices", "--check", *(["--device", DEVICE] if DEVICE else []))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    lines = proc.stdout.splitlines()
    verdicts = [line for line in lines if line.startswith(f"{info.label} {info.name}: ")]
    assert len(verdicts) == 1 and " cases agree (worst " in verdicts[0]
    assert "DISAGREES" not in proc.stdout and "FAILED" not in proc.stdout
    assert lines[0].startswith("checking ") and lines[-1].endswith("with the NumPy reference")
    assert proc.stderr == ""


def test_cli_verbose_shows_every_case_and_usage_errors_exit_2(cli):
    proc = cli("devices", "--check", "-v", "--device", DEVICE or choose_device().label)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for case in selfcheck.cases():
        assert f"    {case.name} " in proc.stdout
    for args in (["--check", "--device", "7:7"], ["--device", "0:0"], ["--check", "--bogus"]):
        proc = cli("devices", *args)
        assert proc.returncode == 2, (args, proc.stdout, proc.stderr)
        assert len(proc.stderr.splitlines()) == 1 and proc.stdout == ""


def test_report_covers_every_op_pattern_edges_mode_and_route(report):
    assert report.agrees and report.error is None, selfcheck.report_lines(report, True)
    results = report.results
    for has_input in (True, False):
        mine = [r for r in results if r.has_input == has_input]
        assert {t for r in mine for t in r.types} == set(REGISTRY), has_input
        assert {r.antialias for r in mine} == set(PATTERNS), has_input
    # each op type alone over an input, to tell which one a device gets wrong
    alone = {r.types[0] for r in results if r.has_input and len(r.types) == 1 and r.frame == 1}
    assert alone == set(REGISTRY)
    assert {r.edges for r in results if r.has_input} == set(EDGE_MODES)
    assert any(len(r.types) > UNROLL_LIMIT and r.has_input for r in results)
    assert any(len(r.types) > UNROLL_LIMIT and not r.has_input for r in results)
    assert {r.case.route for r in results} == {"rgba", "planes", "converted"}
    # the paths a real render takes: adaptive sampling on blank sheets, and every
    # case over an input rendered again from the table of reused maps
    assert any(r.path.startswith("adaptive") for r in results if not r.has_input)
    firsts = [r for r in results if r.has_input and r.frame == 1]
    seconds = [r for r in results if r.frame == 2]
    assert [r.case for r in seconds] == [r.case for r in firsts]
    assert all(r.reused and r.group == "reused" for r in seconds)
    assert not any(r.reused for r in firsts)
    assert all(r.share >= selfcheck.SHARE for r in results)


def test_a_misplaced_picture_makes_the_check_fail_and_exit_1():
    """The check can fail: against the real reference moved by one pixel, every
    case disagrees, the verdict says so and the exit status is 1."""
    report = selfcheck.check_device(DEVICE, reference=shifted)
    assert report.error is None and not report.agrees
    assert len(report.results) == len(selfcheck.cases()) + sum(
        not c.blank for c in selfcheck.cases()
    )
    assert not any(r.agrees for r in report.results)
    assert "DISAGREES: 0/" in selfcheck.verdict_line(report)
    out = io.StringIO()
    assert selfcheck.run_check(DEVICE or choose_device().label, out=out, reference=shifted) == 1
    text = out.getvalue()
    assert "DISAGREES" in text and "do not trust" in text.splitlines()[-1]
    assert "    ops/vortex " in text  # failing cases are listed without -v


def test_a_program_that_fails_to_build_is_one_line_for_the_device(monkeypatch):
    """A real OpenCL build failure (the kernel source replaced by one that does
    not compile): the device's check stops with one line, and exit status 1."""
    from marblevideo.opencl import program

    broken = "__kernel void marble(__global uint *dst) { this is not C; }\n"
    monkeypatch.setattr(program, "program_source", lambda: broken)
    report = selfcheck.check_device(DEVICE)
    assert not report.agrees and "OpenCL build failed" in report.error
    assert "\n" not in report.error and report.stopped_in == selfcheck.cases()[0].name
    line = selfcheck.verdict_line(report)
    assert f": FAILED in {report.stopped_in} (0 cases agreed before it): OpenCL build" in line
    assert "\n" not in line
    out = io.StringIO()
    assert selfcheck.run_check(DEVICE, out=out) == 1
    assert "Traceback" not in out.getvalue()


def test_agreement_counts_pixels_within_the_levels():
    import numpy as np

    a = np.zeros((2, 5, 4), np.uint8)
    b = a.copy()
    b[0, 0, 2] = selfcheck.LEVELS
    b[1, 4, 0] = selfcheck.LEVELS + 1
    assert selfcheck.agreement(a, b) == 0.9
    assert selfcheck.agreement(a[..., 0], b[..., 0]) == 0.9  # planes: per sample
