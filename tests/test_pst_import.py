"""``marblevideo import``: pst-marble designs (tests/data/pst/*.tex) imported and
rendered against what the real pst-marble drew of them (the PNGs beside them,
made by scripts/make_pst_refs.py; no TeX needed here), and the importer's
refusals and outputs.

pst-marble's raster samples each cell at its lower-left corner: the renders
here take the window half a pixel left and down (``view``), without
antialiasing, so that both sample the same points; a pixel agrees when it is
within LEVELS of the reference's colour there or at a neighbour (one pixel).
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers import ROOT, files, one_line, run_main, subprocess_env

from marblevideo.errors import UsageError
from marblevideo.limits import MAX_DESIGN_BYTES
from marblevideo.pstmarble import import_design
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

pytestmark = pytest.mark.tier("fast")

DATA = Path(__file__).resolve().parent / "data" / "pst"
LEVELS, SHARE = 24, 0.995
#: Designs whose every action has the same model in marblevideo.
EXACT = ("rings", "rake", "layouts", "scatter", "stir", "wreath", "curl", "jiggle-contour")


def reference(name: str) -> np.ndarray:
    return cv2.imread(str(DATA / f"{name}.png"))[:, :, ::-1].astype(int)


def render(renderer, doc: dict, n: int) -> np.ndarray:
    """The imported recipe drawn n x n, sampled where pst-marble's raster samples."""
    recipe = parse_recipe({**doc, "antialias": "none"}, "imported.json")
    w, h = recipe.canvas
    geom = geometry(recipe.canvas, (n, n), None, view=(-0.5 * w / n, 0.5 * h / n, w, h))
    return renderer.render(recipe.at(recipe.end_time()), geom, None)[:, :, :3].astype(int)


def agreeing(ours: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Per pixel: within LEVELS of the reference there or at one of its 8 neighbours."""
    h, w = ref.shape[:2]
    pad = np.pad(ref, ((1, 1), (1, 1), (0, 0)), mode="edge")
    best = np.full((h, w), 999)
    for dy in range(3):
        for dx in range(3):
            best = np.minimum(best, np.abs(pad[dy : dy + h, dx : dx + w] - ours).max(axis=2))
    return best <= LEVELS


def compared(renderer, name: str) -> tuple[np.ndarray, np.ndarray, dict]:
    ref = reference(name)
    doc = import_design(DATA / f"{name}.tex")
    ours = render(renderer, doc, ref.shape[1])
    return agreeing(ours, ref), ours, doc


@pytest.mark.parametrize("name", EXACT)
def test_imported_designs_match_pst_marble(renderer, name):
    agree, _, _ = compared(renderer, name)
    assert agree.mean() >= SHARE, f"{name}: only {agree.mean():.4f} of pixels agree"


def test_the_comparison_can_fail(renderer):
    """The same check refuses a design drawn with one action changed."""
    doc = import_design(DATA / "stir.tex")
    turned = [dict(op, turn=-op["turn"]) if op["type"] == "stir" else op for op in doc["ops"]]
    ours = render(renderer, {**doc, "ops": turned}, 128)
    assert agreeing(ours, reference("stir")).mean() < 0.95


def test_jiggle_matches_pst_marbles_exact_contours_and_nearly_its_raster(renderer):
    """pst-marble's raster inverts a jiggle with one approximate Newton step (edges
    off by up to a few pixels); its contour mode draws the exact forward map, which
    is what the recipe's exact inverse matches (EXACT holds jiggle-contour). Against
    the raster: 99% with the neighbourhood, and the misses lie on ink edges."""
    agree, ours, _ = compared(renderer, "jiggle")
    assert agree.mean() >= 0.99
    white = (reference("jiggle") >= 250).all(axis=2) & (ours >= 250).all(axis=2)
    assert not (white & ~agree).any()


def test_seeded_layouts_are_pst_marbles_own_drops():
    """pst-marble's RC4 numbers: the drops land where its generator puts them
    (the scatter design's 50 drops and 50 sprays all match its picture: EXACT)."""
    doc = import_design(DATA / "scatter.tex")
    sprays = [op for op in doc["ops"] if op["type"] == "spray"]
    assert len(sprays) == 30 + 20 and doc["ops"][-1]["type"] == "spray"
    assert len({tuple(op["center"]) for op in doc["ops"]}) == len(doc["ops"])


def test_the_stylus_is_a_stroke_that_matches_away_from_its_path(renderer):
    """pst-marble's stylus is a moving Oseen stylus; the import is a ``stroke``
    (vortex-pair steps), another model: pixels farther than the stroke's width
    from its segment agree as EXACT's do, and the two both drag ink along it."""
    notes = []
    import_design(DATA / "stylus.tex", notes.append)
    assert len(notes) == 1 and "stylus.tex:14:31: note: stylus imported as a stroke" in notes[0]
    agree, ours, doc = compared(renderer, "stylus")
    (stroke,) = [op for op in doc["ops"] if op["type"] == "stroke"]
    (ax, ay), (bx, by) = stroke["points"]
    n = ours.shape[0]
    px, py = np.meshgrid((np.arange(n) + 0.5) * 1000 / n, (np.arange(n) + 0.5) * 1000 / n)
    t = np.clip(
        ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2), 0, 1
    )
    far = np.hypot(px - ax - t * (bx - ax), py - ay - t * (by - ay)) > stroke["width"]
    assert agree[far].mean() >= SHARE and agree.mean() >= 0.98
    rings = render(renderer, {**doc, "ops": doc["ops"][:-1]}, n)
    assert (np.abs(rings - ours).max(axis=2) > LEVELS)[~far].mean() > 0.05


def test_the_mapping_of_each_action():
    doc = import_design(DATA / "rake.tex")
    assert doc["canvas"] == [1000.0, 1000.0] and doc["background"] == [255, 255, 255]
    rakes = [op for op in doc["ops"] if op["type"] == "rake"]
    assert rakes[0]["angle"] == -90 and rakes[0]["tines"] == [-300, -150, 0, 150, 300, 450]
    assert rakes[0]["falloff"] == pytest.approx(40 * 30**2 / 800)
    assert rakes[1]["alpha"] == -60 and rakes[1]["angle"] == 110
    shift = next(op for op in doc["ops"] if op["type"] == "shift")
    assert shift["offset"] == pytest.approx([80 * 0.5, -80 * 3**0.5 / 2])
    (stir,) = import_design(DATA / "wreath.tex")["ops"][-1:]
    falloff = pytest.approx(60 * np.pi * 15**2 / (180 * 1000), abs=1e-6)
    assert stir == {"type": "stir", "center": [500.0, 500.0], "radii": [-150.0], "turn": 30.0,
                    "falloff": falloff}  # fmt: skip
    rings = import_design(DATA / "rings.tex")["ops"][:12]
    assert rings[-1]["color"] == [70, 145, 203]  # colors' first: the innermost ring


def test_a_plain_action_list_and_a_refusal_naming_the_action_and_where(tmp_path):
    plain = tmp_path / "design.ps"
    plain.write_text("0 0 100 [1 0 0] drop\n0 0 [ 200 ] 10 45 20 stir\n")
    doc = import_design(plain)
    assert [op["type"] for op in doc["ops"]] == ["drop", "stir"]
    plain.write_text("0 0 100 [1 0 0] drop\n  0 0 40 20 10 wriggle\n")
    with pytest.raises(UsageError, match=r"design\.ps:2:16: wriggle: .*no marblevideo op"):
        import_design(plain)
    tex = tmp_path / "d.tex"
    tex.write_text("\\psMarble[shadings={0 50 0 5 shading}](10,10)")
    with pytest.raises(UsageError, match=r"d\.tex:1:21: shadings"):
        import_design(tex)


def run_import(*args: str) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "marblevideo", "import", *args]
    return subprocess.run(cmd, capture_output=True, text=True, env=subprocess_env())


def test_the_command_writes_atomically_and_overwrites_only_with_y(tmp_path):
    out = tmp_path / "wreath.json"
    done = run_import(str(DATA / "wreath.tex"), "-o", str(out))
    assert done.returncode == 0, done.stderr
    assert json.loads(out.read_text()) == import_design(DATA / "wreath.tex")
    again = run_import(str(DATA / "wreath.tex"), "-o", str(out))
    assert again.returncode == 2 and "-y" in one_line(again)
    assert run_import(str(DATA / "wreath.tex"), "-o", str(out), "-y").returncode == 0
    printed = run_import(str(DATA / "stir.tex"), "-o", "-")
    assert json.loads(printed.stdout) == import_design(DATA / "stir.tex")
    bad = tmp_path / "bad.tex"
    bad.write_text("\\psMarble[actions={0 0 10 colors 3 concentric-rings 1 2 3 4 5 wriggle}](9,9)")
    refused = run_import(str(bad), "-o", str(tmp_path / "bad.json"), "-y")
    assert refused.returncode == 2 and "bad.tex:1:" in one_line(refused)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.tex", "wreath.json"]


def test_the_docs_example_imports_the_wreath_in_turn_and_renders_it_as_a_video(tmp_path):
    """docs/pst-marble.md: import --animate 6, then the recipe as a video."""
    recipe = tmp_path / "wreath-video.json"
    done = run_import(str(ROOT / "samples" / "wreath.tex"), "-o", str(recipe), "--animate", "6")
    assert done.returncode == 0, done.stderr
    ops = json.loads(recipe.read_text())["ops"]
    drops = [op for op in ops if op["type"] == "drop"]
    assert ops[0]["start"] == 0 and drops[-1]["end"] == pytest.approx(3) and ops[-1]["end"] == 6
    assert all(a["end"] == pytest.approx(b["start"]) for a, b in zip(ops, ops[1:], strict=False))
    video = tmp_path / "wreath.mp4"
    cmd = [sys.executable, "-m", "marblevideo", "--ops", str(recipe), "-o", str(video)]
    cmd += ["--size", "64x64", "--fps", "4", "-q"]
    rendered = subprocess.run(cmd, capture_output=True, text=True, env=subprocess_env())
    assert rendered.returncode == 0, rendered.stderr
    assert video.stat().st_size > 0


def test_psset_settings_apply_and_the_frame_follows_the_size(tmp_path):
    tex = tmp_path / "tall.tex"
    tex.write_text(
        "\\psset[pst-marble]{viscosity=500,background={[0 0 1]}}\n"
        "\\psMarble[actions={0 [0] 10 10 10 rake 0 0 40 (ff8000) drop}](10,20)\n"
    )
    doc = import_design(tex)
    assert doc["canvas"] == [500, 1000] and doc["background"] == [0, 0, 255]
    rake, drop = doc["ops"]
    assert rake["falloff"] == 10 * 10**2 / 500 and drop["center"] == [250, 500]
    assert drop["color"] == [255, 128, 0]


# ---------------------------------------------------------------------------- hostile designs

#: The issue's five lines: a list of 1e308 tines (it grew to 24 GB before).
BIG = r"""\documentclass{article}
\usepackage{pst-marble}
\begin{document}
\psMarble[actions={ 0 0 100 (1d3557) drop 0 [ 1e308 10 0 tines
  ] 40 200 20 rake }](10,10)
\end{document}
"""


def actions(text: str) -> str:
    return f"\\psMarble[actions={{{text}}}](10,10)\n"


# (the design's text, @ where the fault is, what the line says)
HOSTILE = [
    (BIG.replace(" tines", " @tines"), "tines: 1e+308 tines, over the limit of 256 (MAX_LIST)"),
    (actions("0 0 10 colors 1e308 @concentric-rings"),
     "concentric-rings: 1e+308 rings, over the limit of 4,096 (MAX_COUNT)"),
    (actions("0 0 10 colors -3 @concentric-rings"),
     "concentric-rings: -3 rings, expected a count of 0 or more"),
    (actions("0 0 0 0 1 1 colors 1e9 5 @coil-drops"), "coil-drops: 1e+09 drops, over"),
    (actions("0 0 9 9 0 colors 1e12 5 @normal-drops"), "normal-drops: 1e+12 drops"),
    (actions("0 0 9 9 0 colors 5000 5 @uniform-drops"), "uniform-drops: 5000 drops"),
    (actions("0 0 [ 256 1 0 tines ] [ 256 1 0 tines ] 0 colors 5 @serpentine-drops"),
     "serpentine-drops: 65,536 drops, over the limit of 4,096"),
    (actions("1e308 { 0 0 10 (ff0000) drop } @repeat"),
     "repeat: 1e+308 steps, over the limit of 1,000,000"),
    (actions("0 1e-300 1 { pop } @for"), "for: 1e+300 steps, over the limit"),
    (actions("1e16 1 10000000000000002 { pop } @for"), "for: a step of 1 is lost in 1e+16"),
    (actions("900000 { 1 @pop } repeat"), "the design takes over 1,000,000 steps"),
    (actions("/f { @f } def f"), "procedures nested over the limit of 64 (PS_DEPTH)"),
    (actions("200000 { @1 } repeat"), "100,001 values on the stack, over the limit"),
    (actions("5 { 0 0 10 colors 4096 @concentric-rings } repeat"),
     "the design makes 8,192 ops, over the limit of 4,096 (MAX_IMPORT_OPS)"),
    (actions("0 0 1 0 @div (ff0000) drop"), "div: float division by zero"),
    (actions("0 0 -8 0.5 @exp (ff0000) drop"), "exp: a negative number to a fractional"),
    (actions("0 0 1e308 1e308 @mul (ff0000) drop"), "mul: the result is out of range"),
    (actions("0 0 @1e999 (ff0000) drop"), "1e999: a number out of range"),
    ("0 0 10 (ff0000) drop @{ 0", "a { is never closed"),
    ("0 0 10 (ff0000) drop @}", "a } without its {"),
    ("\\psMarble[@actions={0 0 10 (ff0000) drop { 0}](10,10)",
     "\\psMarble: a { in this option is never closed"),
    ("\\psMarble[actions={0 0 10 (ff0000) drop }@}](10,10)", "\\psMarble: a } without its {"),
    (actions("@"), "the design makes no ops (its actions are empty)"),
    ("@", "the design makes no ops"),
    ("@\\documentclass{article}\n\\begin{document}\nhi\n\\end{document}\n",
     "no \\psMarble in this file (\\documentclass is LaTeX, not an action)"),
    ("\\psMarble@(0,10)", "\\psMarble: expected a size > 0"),
    ("\\psMarble[overscan={@(2)}](10,10)", "overscan: expected a number, got (2)"),
]  # fmt: skip


@pytest.mark.parametrize("marked, says", HOSTILE)
def test_hostile_designs_are_refused_in_one_line_before_the_work(tmp_path, marked, says):
    """Each naming the file, the line and column, and the limit (the work bounded
    before it is done: each in well under a second)."""
    path = tmp_path / "d.tex"
    path.write_text(marked.replace("@", ""))
    before = marked[: marked.index("@")]
    where = f"{before.count(chr(10)) + 1}:{len(before) - before.rfind(chr(10))}"
    began = time.perf_counter()
    with pytest.raises(UsageError) as info:
        import_design(path)
    assert time.perf_counter() - began < 1.0
    message = str(info.value)
    assert "\n" not in message and info.value.exit_code == 2
    assert message.startswith(f"{path}:{where}: "), message
    assert says in message, message


def test_a_design_over_the_size_limit_is_refused_unread(tmp_path):
    path = tmp_path / "huge.tex"
    with path.open("wb") as f:
        f.truncate(MAX_DESIGN_BYTES + 1)  # sparse: nothing to read before the refusal
    with pytest.raises(UsageError, match=r"huge\.tex: 16,777,217 bytes, over the limit"):
        import_design(path)


def test_the_issues_design_is_refused_in_a_second_and_under_100_mb(tmp_path):
    """The command line on the five lines under a 1 GB address-space limit (a
    runaway would be a MemoryError): one line, exit 2, the work under 1 s and the
    process under 100 MB resident at its peak (VmHWM: this program's own, not the
    forking test's); nothing written."""
    (tmp_path / "big.tex").write_text(BIG)
    child = (
        "import resource, re, sys, time\n"
        "resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))\n"
        "from marblevideo.cli import main\n"
        "began = time.perf_counter()\n"
        "status = main(['import', 'big.tex', '-o', 'o.json'])\n"
        "took = time.perf_counter() - began\n"
        "peak = re.search(r'VmHWM:\\s*(\\d+)', open('/proc/self/status').read()).group(1)\n"
        "print(took, peak)\n"
        "sys.exit(status)\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", child], cwd=tmp_path, capture_output=True, text=True,
        env=subprocess_env(), timeout=60,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "tines: 1e+308 tines, over the limit of 256" in one_line(proc)
    took, kilobytes = proc.stdout.split()  # the work's seconds, the peak resident size
    assert float(took) < 1.0 and int(kilobytes) < 100 * 1024, proc.stdout
    assert files(tmp_path) == ["big.tex"]


@pytest.mark.parametrize(
    "design, output, says",
    [
        ("", "e.json", "e.tex:1:1: the design makes no ops (its actions are empty)"),
        (actions("0 0 100 (1d3557) drop"), "out.png",
         "out.png: a recipe is written as .json; give a .json name"),
        (actions("0 0 100 (1d3557) drop"), "adir", "adir: output is a folder; give a file name"),
    ],
)  # fmt: skip
def test_the_command_refuses_an_empty_design_and_an_output_not_json(
    tmp_path, monkeypatch, design, output, says
):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "e.tex").write_text(design)
    (tmp_path / "adir").mkdir()
    proc = run_main("import", "e.tex", "-o", output)
    assert proc.returncode == 2 and one_line(proc) == f"marblevideo: {says}"
    assert files(tmp_path) == ["adir", "e.tex"] and not list((tmp_path / "adir").iterdir())
