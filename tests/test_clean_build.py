"""The kernels build silently on every CPU: a vector width the device holds, no
compiler warnings at their source, nothing on stderr from a cold build.

PoCL's distribution builds compile for the CPU named by POCL_KERNELLIB_NAME
(sse2, avx2, avx512, ...), so one machine checks the code generated for the
instruction sets it has, AVX2 on an AVX-512 machine included. Every build here
uses an empty, private PoCL cache (a cached binary would say nothing).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import ROOT, fresh_renderer, pythonpath

from marblevideo.errors import DeviceError, UsageError
from marblevideo.opencl.program import LANES_VARIABLE, cpu_lanes

pytestmark = pytest.mark.tier("integration")

SAMPLES = ROOT / "samples"


def _cpu_flags() -> set[str]:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return set()
    line = next((x for x in text.splitlines() if x.startswith("flags")), "")
    return set(line.partition(":")[2].split())


def _pocl(renderer) -> bool:
    return "Portable Computing Language" in renderer.info.platform


# PoCL kernel library -> the vector width a CPU with that instruction set reports
TARGETS = [("sse2", 4, "sse2"), ("avx2", 8, "avx2"), ("avx512", 16, "avx512f")]
HOST_TARGETS = [(lib, width) for lib, width, flag in TARGETS if flag in _cpu_flags()]


def _cold_env(tmp_path, **extra) -> dict:
    cache = tmp_path / "cache"
    cache.mkdir(exist_ok=True)
    env = {k: v for k, v in os.environ.items() if k not in ("POCL_KERNELLIB_NAME", LANES_VARIABLE)}
    env.update(
        POCL_CACHE_DIR=str(cache / "pocl"),
        XDG_CACHE_HOME=str(cache),
        PYTHONPATH=pythonpath(),
        **extra,
    )
    return env


def test_cpu_lanes_follow_the_native_width():
    assert [cpu_lanes(n) for n in (16, 8, 4)] == [16, 8, 4]  # AVX-512, AVX2, SSE
    assert cpu_lanes(32) == 16 and cpu_lanes(1) == 4 and cpu_lanes(0) == 4
    assert cpu_lanes(16, "8") == 8 and cpu_lanes(4, "16") == 16
    for bad in ("7", "x", "32"):
        with pytest.raises(UsageError, match=LANES_VARIABLE):
            cpu_lanes(16, bad)


def test_the_renderer_takes_the_devices_width(renderer):
    dev = renderer.info.device
    if "CPU" not in renderer.info.kind:
        assert renderer.lanes == 1
        return
    native = max(dev.native_vector_width_float, dev.preferred_vector_width_float)
    if not os.environ.get(LANES_VARIABLE):
        assert renderer.lanes == cpu_lanes(native)
    assert renderer.yuv_lanes == renderer.lanes <= max(native, 4)
    with pytest.raises(UsageError, match="lanes must be"):
        fresh_renderer(lanes=3)


BUILD_EVERY_KIND = """
import json, logging, sys
from marblevideo.opencl.renderer import Renderer
from marblevideo.opencl.program import Structure, UNROLL_LIMIT
logs = []
class Keep(logging.Handler):
    def emit(self, record):
        logs.append(record.getMessage())
logger = logging.getLogger("marblevideo")
logger.setLevel(logging.DEBUG)
logger.addHandler(Keep())
from marblevideo.ops import REGISTRY
ops = tuple(REGISTRY)  # every op section
for lanes in (None, 1):
    renderer = Renderer(lanes=lanes)
    for structure in (
        Structure(ops, "rgss", "clamp", True),
        Structure(ops, "quincunx", "background", False),
        Structure(ops * (UNROLL_LIMIT // 7 + 1), "none", "mirror", True),
    ):
        renderer.kernel_for(structure)
print(json.dumps(logs))
"""


@pytest.mark.parametrize("target", HOST_TARGETS, ids=[t[0] for t in HOST_TARGETS])
def test_kernels_build_without_a_warning(renderer, tmp_path, target):
    """Built with warnings on (the --verbose build), for each instruction set this
    CPU has, at that set's width: the build log and stderr hold no warning."""
    if not _pocl(renderer):
        pytest.skip("PoCL's kernel libraries name the CPU targets")
    lib, width = target
    env = _cold_env(tmp_path, POCL_KERNELLIB_NAME=lib, **{LANES_VARIABLE: str(width)})
    proc = subprocess.run(
        [sys.executable, "-c", BUILD_EVERY_KIND],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    logs = json.loads(proc.stdout)
    builds = [entry for entry in logs if entry.startswith("built the kernels")]
    assert len(builds) == 6, logs
    assert all("empty build log" in entry for entry in builds), builds
    assert "warning" not in proc.stderr


QUIET_RUNS = {
    "still": ["coffee.jpg", "--ops", "comb-wave.json", "-o", "{out}/o.png", "--size", "64x48"],
    "blank": ["--ops", "figure6.json", "-o", "{out}/o.png", "--size", "96x96"],
    "video": ["coffee.mp4", "--ops", "swirl.json", "-o", "{out}/o.mp4", "--end", "0.2"],
    "svg": ["--ops", "figure6.json", "-o", "{out}/o.svg", "--size", "64x64"],
}


@pytest.mark.parametrize(
    "target",
    [None, "avx2", "avx2-16"],
    ids=["host", "avx2", "avx2-forced-16-lanes"],
)
def test_quiet_runs_print_nothing_on_a_cold_cache(tmp_path, target):
    """-q on an empty cache: not a byte on stderr, whatever the CPU target and even
    at a width the CPU does not hold (which clang would warn about)."""
    extra = {}
    if target is not None:
        extra["POCL_KERNELLIB_NAME"] = "avx2"
        if target.endswith("16"):
            extra[LANES_VARIABLE] = "16"
        if "avx2" not in _cpu_flags():
            pytest.skip("this CPU has no AVX2")
    for name, args in QUIET_RUNS.items():
        out = tmp_path / name
        out.mkdir()
        proc = subprocess.run(
            [sys.executable, "-m", "marblevideo", *(a.format(out=out) for a in args), "-q"],
            cwd=SAMPLES,
            env=_cold_env(tmp_path, **extra),
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert proc.returncode == 0, (name, proc.stderr)
        assert proc.stderr == "", (name, proc.stderr)
        assert any(out.iterdir()), name


def test_verbose_names_the_device_and_shows_the_build(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "marblevideo", *QUIET_RUNS["blank"][:-2], "--verbose"]
        + ["-o", str(tmp_path / "o.png"), "--size", "32x32"],
        cwd=SAMPLES,
        env=_cold_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    lines = [x for x in proc.stderr.splitlines() if x.startswith("marblevideo: ")]
    assert any("rendering on" in x and "lane" in x for x in lines), proc.stderr
    assert any(x.startswith("marblevideo: built the kernels for") for x in lines), proc.stderr


def test_a_failed_build_is_one_line_naming_its_log(renderer):
    source = "__kernel void broken(__global float *x) { x[0] = undefined_name; }"
    with pytest.raises(DeviceError) as caught:
        renderer.build_program(source, ["-DLANES=1"])
    message = str(caught.value)
    assert "\n" not in message and "OpenCL build failed" in message
    assert "undefined_name" in message, message
    log = Path(message.rsplit("full log: ", 1)[1].rstrip(")"))
    try:
        assert "undefined_name" in log.read_text() and "-DLANES=1" in log.read_text()
    finally:
        log.unlink()
