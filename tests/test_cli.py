"""The command line, end to end: every run goes through a real
``python -m marblevideo`` subprocess on the real OpenCL device.

Contract checked: a recipe fault of any kind is exit status 2 with one stderr
line naming the file and the JSON path, no traceback, nothing written; an
existing output is never replaced without -y; stills in and out in every
format; and the built wheel carries the kernels.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers import ROOT, files, one_line, subprocess_env

pytestmark = pytest.mark.tier("integration")

RECIPE = {
    "canvas": [64, 48],
    "antialias": "none",
    "ops": [
        {"type": "drop", "center": [32, 24], "radius": 10, "color": "#cc2200"},
        {
            "type": "tine",
            "point": [0, 24],
            "angle": 0,
            "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 2, "v": 20}]},
            "lambda": 6,
        },
    ],
}


def write_recipe(folder: Path, doc, name: str = "r.json") -> Path:
    path = folder / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return path


# ---------------------------------------------------------------------------- recipe faults


def _with(change):
    doc = json.loads(json.dumps(RECIPE))
    change(doc)
    return doc


FAULTS = {
    "invalid-json": ('{\n  "ops": [\n    {"type": "drop",}\n  ]\n}', "", "line 3, column"),
    "unknown-op": (_with(lambda d: d["ops"][0].update(type="dorp")), "ops[0].type", "'drop'"),
    "misspelled-field": (
        _with(lambda d: d["ops"][1].update(lamda=d["ops"][1].pop("lambda"))),
        "ops[1]",
        "unknown field 'lamda'",
    ),
    "unknown-top-field": (_with(lambda d: d.update(colour="#fff")), "", "unknown field"),
    "wrong-type": (_with(lambda d: d["ops"][0].update(radius="10")), "ops[0].radius", "number"),
    "nan": (json.dumps(RECIPE).replace('"radius": 10', '"radius": NaN'), "ops[0].radius", "NaN"),
    "infinity": (
        json.dumps(RECIPE).replace('"lambda": 6', '"lambda": -Infinity'),
        "ops[1].lambda",
        "Infinity",
    ),
    "out-of-range": (_with(lambda d: d["ops"][1].update({"lambda": -2})), "ops[1].lambda", "> 0"),
    "huge": (_with(lambda d: d["ops"][0].update(radius=1e31)), "ops[0].radius", "1e30"),
    "key-times": (
        _with(lambda d: d["ops"][1]["alpha"]["keys"][1].update(t=0)),
        "ops[1].alpha.keys[1].t",
        "increase",
    ),
    "version": (_with(lambda d: d.update(marblevideo=2)), "marblevideo", "expected 1"),
    "missing-field": (_with(lambda d: d["ops"][0].pop("center")), "ops[0]", "'center'"),
    "no-ops": (_with(lambda d: d.pop("ops")), "", "'ops'"),
    "not-an-object": ("[1, 2, 3]", "", "expected"),
}


@pytest.mark.parametrize("name", sorted(FAULTS))
def test_recipe_faults_exit_2_with_file_and_path(cli, tmp_path, name):
    doc, path, expected = FAULTS[name]
    write_recipe(tmp_path, doc)
    proc = cli("--ops", "r.json", "-o", "out.png")
    assert proc.returncode == 2
    line = one_line(proc)
    prefix = f"marblevideo: r.json: {path}: " if path else "marblevideo: r.json: "
    assert line.startswith(prefix), line
    assert expected in line, line
    assert files(tmp_path) == ["r.json"]  # no output, no temporary file


def test_recipe_fault_before_the_input_is_opened(cli, tmp_path):
    """A bad recipe is reported even when the input does not exist."""
    write_recipe(tmp_path, FAULTS["out-of-range"][0])
    proc = cli("missing.mp4", "--ops", "r.json", "-o", "out.mp4")
    assert proc.returncode == 2 and "ops[1].lambda" in one_line(proc)


def test_missing_and_unreadable_recipe(cli, tmp_path):
    proc = cli("--ops", "nope.json", "-o", "out.png")
    assert proc.returncode == 2 and "nope.json" in one_line(proc)
    (tmp_path / "bin.json").write_bytes(b"\xff\xfe\x00garbage")
    proc = cli("--ops", "bin.json", "-o", "out.png")
    assert proc.returncode == 2 and "bin.json" in one_line(proc)


def test_usage_errors_exit_2(cli, tmp_path):
    write_recipe(tmp_path, RECIPE)
    for args in (
        [],
        ["--ops", "r.json"],
        ["--ops", "r.json", "-o", "o.png", "--size", "12"],
        ["--ops", "r.json", "-o", "o.png", "--size", "0x10"],
        ["--ops", "r.json", "-o", "o.png", "--time", "soon"],
        ["--ops", "r.json", "-o", "o.png", "--bogus"],
        ["--ops", "r.json", "-o", "o.xyz"],
        ["--ops", "r.json", "-o", "noext"],
        ["devices", "--bogus"],
    ):
        proc = cli(*args)
        assert proc.returncode == 2, (args, proc.stderr)
        one_line(proc)
    assert files(tmp_path) == ["r.json"]


def test_blank_sheet_needs_a_canvas(cli, tmp_path):
    write_recipe(tmp_path, {"ops": []})
    for out in ("o.png", "o.mp4"):
        proc = cli("--ops", "r.json", "-o", out)
        assert proc.returncode == 2
        assert one_line(proc).startswith("marblevideo: r.json: canvas: ")
    assert files(tmp_path) == ["r.json"]


# ---------------------------------------------------------------------------- overwrite


def test_no_overwrite_without_y(cli, tmp_path):
    write_recipe(tmp_path, RECIPE)
    for name in ("o.png", "o.mp4"):
        (tmp_path / name).write_bytes(b"precious bytes")
        timing = ["--duration", "0.2"] if name.endswith(".mp4") else []
        proc = cli("--ops", "r.json", "-o", name, *timing)
        assert proc.returncode == 2 and "-y" in one_line(proc)
        assert (tmp_path / name).read_bytes() == b"precious bytes"
    assert files(tmp_path) == ["o.mp4", "o.png", "r.json"]
    proc = cli("--ops", "r.json", "-o", "o.png", "-y", "-q")
    assert proc.returncode == 0, proc.stderr
    assert cv2.imread(str(tmp_path / "o.png")).shape == (48, 64, 3)


# ---------------------------------------------------------------------------- other commands


def test_devices_lists_the_device(cli):
    proc = cli("devices")
    assert proc.returncode == 0, proc.stderr
    assert "platform:" in proc.stdout and "* " in proc.stdout
    if not os.environ.get("MARBLEVIDEO_TEST_DEVICE"):
        assert "Portable Computing Language" in proc.stdout or "GPU" in proc.stdout


def test_schema_is_valid_json_schema(cli):
    from jsonschema import Draft202012Validator

    proc = cli("schema")
    assert proc.returncode == 0
    schema = json.loads(proc.stdout)
    Draft202012Validator.check_schema(schema)
    Draft202012Validator(schema).validate(RECIPE)


def test_help_and_version(cli):
    proc = cli("--help")
    assert proc.returncode == 0 and "exit status" in proc.stdout
    proc = cli("--version")
    assert proc.returncode == 0 and proc.stdout.startswith("marblevideo ")


# ---------------------------------------------------------------------------- stills


def _photo(alpha: bool) -> np.ndarray:
    rng = np.random.default_rng(3)
    img = rng.integers(0, 256, (30, 40, 4 if alpha else 3), np.uint8)
    if alpha:
        img[..., 3] = np.linspace(0, 255, 40, dtype=np.uint8)[None, :]
    return img


@pytest.mark.parametrize("src_ext", [".png", ".jpg", ".tif", ".webp"])
@pytest.mark.parametrize("dst_ext", [".png", ".jpeg", ".tiff", ".webp"])
def test_stills_in_every_format(cli, tmp_path, src_ext, dst_ext):
    alpha = src_ext != ".jpg"
    params = [cv2.IMWRITE_WEBP_QUALITY, 101] if src_ext == ".webp" else []
    assert cv2.imwrite(str(tmp_path / f"in{src_ext}"), _photo(alpha), params)
    write_recipe(tmp_path, {k: v for k, v in RECIPE.items() if k != "canvas"})
    proc = cli(f"in{src_ext}", "--ops", "r.json", "-o", f"out{dst_ext}", "-q")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    out = cv2.imread(str(tmp_path / f"out{dst_ext}"), cv2.IMREAD_UNCHANGED)
    keeps_alpha = alpha and dst_ext != ".jpeg"
    assert out.shape == (30, 40, 4 if keeps_alpha else 3)
    if keeps_alpha:  # the alpha ramp survives the marbling outside the drop
        assert out[0, -1, 3] > 200 and out[0, 0, 3] < 50
    assert files(tmp_path) == sorted([f"in{src_ext}", f"out{dst_ext}", "r.json"])


def test_time_and_size(cli, tmp_path):
    write_recipe(tmp_path, RECIPE)
    for t in ("0", "2"):
        proc = cli("--ops", "r.json", "-o", f"t{t}.png", "--time", t, "--size", "128x96", "-q")
        assert proc.returncode == 0, proc.stderr
    proc = cli("--ops", "r.json", "-o", "end.png", "--size", "128x96", "-q")
    assert proc.returncode == 0, proc.stderr
    t0, t2, end = (cv2.imread(str(tmp_path / n)) for n in ("t0.png", "t2.png", "end.png"))
    assert t0.shape == (96, 128, 3)
    assert np.array_equal(t2, end)  # default: the end of the animation
    assert not np.array_equal(t0, t2)  # the tine moved the drop


def test_wrote_note_unless_quiet(cli, tmp_path):
    write_recipe(tmp_path, RECIPE)
    proc = cli("--ops", "r.json", "-o", "o.png")
    assert proc.returncode == 0 and proc.stderr.strip() == "wrote o.png"


# ---------------------------------------------------------------------------- packaging


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", "-q", "-w", str(out)],
        check=True,
        capture_output=True,
        timeout=300,
    )
    (found,) = out.glob("marblevideo-*.whl")
    return found


@pytest.mark.slow
def test_built_wheel_contains_and_serves_the_kernels(wheel, tmp_path):
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
        kernels = [
            f"marblevideo/kernels/{p.relative_to(ROOT / 'kernels')}"
            for p in (ROOT / "kernels").rglob("*.cl")
        ]
        assert "marblevideo/kernels/ops/ink.cl" in kernels and set(kernels) <= set(names)
        shipped = zf.read("marblevideo/kernels/walk.cl").decode()
        recipes = {p.name for p in (ROOT / "samples").glob("*.json")}
        assert {f"marblevideo/samples/{n}" for n in recipes} <= set(names)
        assert (
            zf.read("marblevideo/samples/figure6.json")
            == (ROOT / "samples" / "figure6.json").read_bytes()
        )
        assert "marblevideo/samples/coffee.mp4" not in names  # the wheel stays small
    assert shipped == (ROOT / "kernels" / "walk.cl").read_text()

    venv = tmp_path / "venv"
    subprocess.run(
        [sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
        check=True,
        timeout=120,
    )
    py = venv / "bin" / "python"
    # the dependencies installed for this interpreter (a venv's own are not the
    # system's), after the new venv's site-packages, where the wheel goes
    site = subprocess.run(
        [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True,
        capture_output=True,
        text=True,
        timeout=60,
    ).stdout.strip()
    ours = {sysconfig.get_paths()[k] for k in ("purelib", "platlib")}
    (Path(site) / "_test_dependencies.pth").write_text("\n".join(sorted(ours)) + "\n")
    subprocess.run(
        [str(py), "-m", "pip", "install", "--no-deps", "-q", str(wheel)],
        check=True,
        capture_output=True,
        timeout=300,
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    probe = (
        "import marblevideo, marblevideo.opencl.program as r; from importlib import resources;"
        "print(marblevideo.__file__);"
        "print(resources.files('marblevideo') / 'kernels' / 'walk.cl');"
        "print(len(r.program_source()))"
    )
    proc = subprocess.run(
        [str(py), "-c", probe], cwd=outside, env=env, capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 0, proc.stderr
    package, kernel, length = proc.stdout.split("\n")[:3]
    assert package.startswith(str(venv)) and kernel.startswith(str(venv)), proc.stdout
    from marblevideo.opencl.program import program_source

    assert Path(kernel).is_file() and int(length) == len(program_source())

    # the console script of the installed package renders a still
    write_recipe(outside, RECIPE)
    proc = subprocess.run(
        [str(venv / "bin" / "marblevideo"), "--ops", "r.json", "-o", "o.png", "-q"],
        cwd=outside,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert cv2.imread(str(outside / "o.png")).shape == (48, 64, 3)

    # the gallery finds its recipe, the bundled figure6.json, in the installed package
    proc = subprocess.run(
        [str(py), "-m", "marblevideo.gallery", "-o", "steps.png", "--size", "48"],
        cwd=outside,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert cv2.imread(str(outside / "steps.png")).shape == (2 * 76 + 6, 5 * 54 + 6, 3)
    probe = "import marblevideo; print(marblevideo.samples_path('sphere-uv.png'))"
    proc = subprocess.run(
        [str(py), "-c", probe], cwd=outside, env=env, capture_output=True, text=True, timeout=60
    )
    assert proc.stdout.startswith(str(venv)) and proc.stdout.strip().endswith(".png"), proc


def test_python_dash_m_and_main_entry_agree(cli, tmp_path):
    """``python -m marblevideo`` and the console script's ``marblevideo.cli:main``."""
    write_recipe(tmp_path, FAULTS["out-of-range"][0])
    by_module = cli("--ops", "r.json", "-o", "o.png")
    by_main = subprocess.run(
        [sys.executable, "-c", "import sys, marblevideo.cli as c; sys.exit(c.main())"]
        + ["--ops", "r.json", "-o", "o.png"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
        env=subprocess_env(),
    )
    assert by_module.returncode == by_main.returncode == 2
    assert by_module.stderr == by_main.stderr
