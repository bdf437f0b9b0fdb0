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
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers import ROOT, one_line, subprocess_env

from marblevideo.errors import UsageError
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
