"""Device self-test: a fixed set of small renders on one OpenCL device, each
compared with the NumPy reference (``marblevideo devices --check``).

Conventions:

- Agreement is the share of pixels whose every channel lies within
  :data:`LEVELS` of the reference (for I420 frames: of plane samples); a case
  agrees when that share is at least :data:`SHARE`. These are the test suite's
  tolerances: the tests import them from here.
- Every device gets a fresh :class:`~marblevideo.opencl.renderer.Renderer` with the
  renderer's defaults for that device (vector code on CPUs, one pixel
  per work-item on GPUs; adaptive sampling on blank sheets, reused maps over
  inputs), so the check runs the code a real render of that device runs.
- The cases (:mod:`marblevideo.opencl.selfcheck_cases`) are derived from the
  real lists: every op type of the registry (:data:`marblevideo.ops.REGISTRY`,
  with its example), every antialiasing pattern
  (:data:`marblevideo.recipe.antialias.PATTERNS`) over an input and on a blank sheet,
  every edges mode (:data:`marblevideo.recipe.frame.EDGE_MODES`), a recipe longer
  than :data:`~marblevideo.opencl.program.UNROLL_LIMIT` (the loop walk), I420 frames
  warped plane by plane and converted between matrices; every case over an
  input is rendered a second time, identically, which must come from the table
  of reused maps (group ``reused``).
- The input is a deterministic picture made in code
  (:func:`~marblevideo.opencl.selfcheck_cases.input_picture`).
  Sizes are small: the whole set renders in seconds on two CPU cores once the
  programs are built.
- ``reference`` is a function like :func:`marblevideo.reference.render`
  (``(spec, geom, image or None) -> RGBA``); the I420 expectations are made
  from it too. Its results are kept per case in ``expected`` (a dict), so
  several devices share one reference run.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from marblevideo.media.yuv import YuvMatrix
from marblevideo.opencl.device import HOW_TO_GET_ONE, DeviceInfo, choose_device, list_devices
from marblevideo.opencl.program import UNROLL_LIMIT
from marblevideo.opencl.renderer import Renderer
from marblevideo.opencl.selfcheck_cases import INPUT_SIZE, Case, cases, input_picture
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import FrameSpec, Geometry, geometry
from marblevideo.reference import render as reference_render
from marblevideo.reference.yuv import i420_to_rgba, render_planes, rgba_to_i420

#: A pixel agrees when every channel is within this many levels of the reference.
LEVELS = 4
#: A render agrees when at least this share of its pixels agree.
SHARE = 0.99

Reference = Callable[[FrameSpec, Geometry, "np.ndarray | None"], np.ndarray]

#: Case groups in the order they are reported, with their descriptions.
GROUPS = {
    "ops": "each op type over an input",
    "antialias": "each antialiasing pattern over an input",
    "edges": "each edges mode over an input",
    "blank": "each antialiasing pattern on a blank sheet (adaptive)",
    "long": "a recipe longer than the unrolled walk (loop walk)",
    "i420": "I420 frames: planes warped as they are, and converted",
    "reused": "each input case again, from the table of reused maps",
}

OUTPUT_SIZE = (80, 60)
BLANK_SIZE = (88, 60)  # wider than the canvas: the plane beyond it shows too
PLANES = YuvMatrix.of(1, 1)  # BT.709, limited range
CONVERTED = (YuvMatrix.of(5, 1), YuvMatrix.of(9, 2))  # BT.601 limited -> BT.2020 full


def agreement(a: np.ndarray, b: np.ndarray, levels: int = LEVELS) -> float:
    """Share of pixels of ``a`` within ``levels`` of ``b`` in every channel
    (arrays of equal shape: (H, W, C) images, or 2-D planes such as I420)."""
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16))
    if diff.ndim == 3:
        diff = diff.max(axis=2)
    return float((diff <= levels).mean())


@dataclass
class CaseResult:
    """How one render went. ``share``: of pixels within LEVELS of the reference
    (None when it failed to run: ``error`` says why); ``path``: what the
    renderer did (walk, adaptive, table, planes...)."""

    case: Case
    frame: int  # 1: the first render; 2: the same frame again (group "reused")
    types: tuple[str, ...]
    antialias: str
    edges: str
    share: float | None = None
    reused: bool = False
    path: str = ""
    note: str = ""
    error: str | None = None

    @property
    def name(self) -> str:
        return self.case.name if self.frame == 1 else f"reused/{self.case.name}"

    @property
    def group(self) -> str:
        return self.case.group if self.frame == 1 else "reused"

    @property
    def has_input(self) -> bool:
        return not self.case.blank

    @property
    def agrees(self) -> bool:
        """Within tolerance, and a second frame came from the table."""
        if self.error is not None or self.share is None or self.share < SHARE:
            return False
        return self.frame == 1 or self.reused


@dataclass
class DeviceReport:
    """The check of one device: its results in case order, and ``error``: the one
    line of a failure that stopped it (the device could not be opened, or in the
    case named ``stopped_in`` a program failed to build or an OpenCL call
    failed); the cases after it did not run."""

    label: str
    name: str
    platform: str
    kind: str
    results: list[CaseResult] = field(default_factory=list)
    error: str | None = None
    stopped_in: str | None = None
    seconds: float = 0.0

    @property
    def agrees(self) -> bool:
        return self.error is None and bool(self.results) and all(r.agrees for r in self.results)

    @property
    def worst(self) -> float | None:
        shares = [r.share for r in self.results if r.share is not None]
        return min(shares) if shares else None


def _expected(case: Case, reference: Reference, image: np.ndarray, geom: Geometry, spec):
    if case.route == "planes":
        return render_planes(spec, geom, rgba_to_i420(image, PLANES), PLANES, render=reference)
    if case.route == "converted":
        src, dst = CONVERTED
        return rgba_to_i420(reference(spec, geom, i420_to_rgba(rgba_to_i420(image, src), src)), dst)
    return reference(spec, geom, None if case.blank else image)


def _path(renderer, case: Case, spec: FrameSpec, w: int, h: int) -> str:
    walk = "loop walk" if len(spec.ops) > UNROLL_LIMIT else "walk"
    if renderer.last_reused:
        walk = "table"
    if renderer.last_full_pixels is not None:
        walk = f"adaptive, {renderer.last_full_pixels} of {w * h} pixels in full"
    return {"planes": "planes, ", "converted": "converted, "}.get(case.route, "") + walk


def _run(renderer, case: Case, spec, geom: Geometry, image: np.ndarray) -> np.ndarray:
    if case.route == "planes":
        return renderer.render_i420(spec, geom, rgba_to_i420(image, PLANES), PLANES, PLANES)
    if case.route == "converted":
        src, dst = CONVERTED
        return renderer.render_i420(spec, geom, rgba_to_i420(image, src), src, dst)
    return renderer.render(spec, geom, None if case.blank else image)


def _one_line(exc: BaseException) -> str:
    """The first line of an error; named by its type unless it is one of ours
    (whose messages notify what failed)."""
    from marblevideo.errors import MarbleError

    text = str(exc).strip()
    first = text.splitlines()[0] if text else ""
    if isinstance(exc, MarbleError) and first:
        return first
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__


def check_device(
    device: str | DeviceInfo | None = None,
    *,
    reference: Reference | None = None,
    expected: dict | None = None,
) -> DeviceReport:
    """Render every case of :func:`cases` on ``device`` (a choice as for
    ``--device``, a DeviceInfo, or None for the default device) and compare it
    with ``reference`` (default :func:`marblevideo.reference.render`).

    Never raises for the device's own faults: a device that cannot be opened,
    a program that fails to build or an OpenCL error ends the device's check
    with ``report.error`` set (one line). A ``device`` that matches no device
    raises :class:`~marblevideo.errors.UsageError` as ``--device`` does.
    """
    info = device if isinstance(device, DeviceInfo) else choose_device(device)
    reference = reference or reference_render
    expected = {} if expected is None else expected
    report = DeviceReport(info.label, info.name, info.platform, info.kind)
    image = input_picture()
    started = time.perf_counter()
    try:
        renderer = Renderer(info.label)
    except Exception as exc:  # the device cannot be opened: it fails, the others go on
        renderer, report.error = None, _one_line(exc)
    try:
        for case in cases() if renderer else ():
            _check_case(renderer, case, image, reference, expected, report.results)
    except _Stopped:
        failed = report.results[-1]
        report.error, report.stopped_in = failed.error, failed.name
    report.seconds = time.perf_counter() - started
    return report


class _Stopped(Exception):
    """The last result failed to run (its ``error`` says why): the device fails."""


def _check_case(renderer, case: Case, image, reference, expected: dict, results: list) -> None:
    """Append ``case``'s results (two frames over an input, one on a blank sheet)."""
    recipe = parse_recipe(case.recipe, f"selfcheck {case.name}")
    spec = recipe.at(recipe.end_time())
    out_size = BLANK_SIZE if case.blank else OUTPUT_SIZE
    geom = geometry(recipe.canvas, out_size, None if case.blank else INPUT_SIZE)
    if case.name not in expected:
        expected[case.name] = _expected(case, reference, image, geom, spec)
    want = expected[case.name]
    types = tuple(op.type for op in spec.ops)
    for frame in (1,) if case.blank else (1, 2):
        result = CaseResult(case, frame, types, spec.antialias, spec.edges)
        results.append(result)
        try:
            got = _run(renderer, case, spec, geom, image)
        except Exception as exc:  # a build or OpenCL failure: the device fails
            result.error = _one_line(exc)
            raise _Stopped from None
        result.reused = bool(renderer.last_reused)
        result.path = _path(renderer, case, spec, *out_size)
        if got.shape != want.shape:
            result.share, result.note = 0.0, f"shape {got.shape}, expected {want.shape}"
        else:
            result.share = agreement(got, want)
        if frame == 2 and not result.reused:
            result.note = "the second frame did not come from the table"


def _percent(share: float | None) -> str:
    return "-" if share is None else f"{100 * share:.2f}%"


def case_line(result: CaseResult) -> str:
    """One case's detail: name, agreement, what the renderer did, and its fault."""
    verdict = "ok" if result.agrees else "FAILED" if result.share is None else "DISAGREES"
    text = f"    {result.name:<28} {_percent(result.share):>8}  {verdict:<9} {result.path}"
    note = result.error or result.note
    return f"{text}  ({note})" if note else text.rstrip()


def verdict_line(report: DeviceReport) -> str:
    """The device's one-line verdict."""
    head = f"{report.label} {report.name}"
    good = sum(r.agrees for r in report.results)
    if report.error:
        where = f" in {report.stopped_in} ({good} cases agreed before it)"
        return f"{head}: FAILED{where if report.stopped_in else ''}: {report.error}"
    verdict = "" if report.agrees else "DISAGREES: "
    return (
        f"{head}: {verdict}{good}/{len(report.results)} cases agree (worst "
        f"{_percent(report.worst)} of pixels within {LEVELS} levels; {report.seconds:.1f} s)"
    )


def report_lines(report: DeviceReport, verbose: bool = False) -> list[str]:
    """Per group a line (cases agreeing, worst share), the failing cases' detail
    (every case's with ``verbose``), then :func:`verdict_line`."""
    lines = []
    for group, title in GROUPS.items():
        mine = [r for r in report.results if r.group == group]
        if not mine:
            continue
        good = sum(r.agrees for r in mine)
        worst = min((r.share for r in mine if r.share is not None), default=None)
        lines.append(f"  {title:<56} {good:>2}/{len(mine):<2} worst {_percent(worst)}")
        # a failure to run is in the verdict line already
        lines += [case_line(r) for r in mine if verbose or not (r.agrees or r.error)]
    lines.append(verdict_line(report))
    return lines


def run_check(
    device: str | None = None,
    *,
    verbose: bool = False,
    out=None,
    reference: Reference | None = None,
) -> int:
    """``marblevideo devices --check``: check ``device`` (a ``--device`` choice),
    or every device found, printing to ``out`` (default stdout). Returns the exit
    status: 0 when every checked device agrees, 1 when one disagrees or fails (or
    there is none). A choice that matches no device raises UsageError (exit 2)."""
    out = out or sys.stdout

    def notify(text: str) -> None:
        print(text, file=out, flush=True)

    devices = [choose_device(device)] if device else list_devices()
    if not devices:
        notify(f"no OpenCL device found; {HOW_TO_GET_ONE}")
        return 1
    expected: dict = {}
    reports = []
    for info in devices:
        notify(f"checking {info.label} {info.name} [{info.kind}], platform: {info.platform}")
        report = check_device(info, reference=reference, expected=expected)
        for line in report_lines(report, verbose):
            notify(line)
        reports.append(report)
    bad = [r.label for r in reports if not r.agrees]
    if bad:
        notify(
            f"{len(bad)} of {len(reports)} checked devices disagree with the NumPy "
            f"reference or fail: {', '.join(bad)}; do not trust their output"
        )
        return 1
    one = len(reports) == 1
    notify(
        f"{'the' if one else 'all'} {len(reports)} checked device{'' if one else 's'} "
        f"agree{'s' if one else ''} with the NumPy reference"
    )
    return 0
