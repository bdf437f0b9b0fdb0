"""The stage gallery (``python -m marblevideo.gallery``) and the bundled samples:
stages follow from the recipe's windows, each picture shows exactly its ops,
and the command line fails in one line."""

from __future__ import annotations

import json
import subprocess
import sys

import cv2
import numpy as np
import pytest
from helpers import ROOT, subprocess_env

from marblevideo import load_recipe, parse_recipe, samples_path
from marblevideo.gallery import stages, strip, upto
from marblevideo.marbler import Marbler

pytestmark = pytest.mark.tier("fast")


def spans(recipe):
    return [(s.label, s.first, s.last) for s in stages(recipe)]


def test_samples_path_finds_the_checkouts_samples_and_names_the_others():
    assert samples_path("figure6.json") == ROOT / "samples" / "figure6.json"
    with pytest.raises(FileNotFoundError, match="no sample 'nope.json'.*figure6.json"):
        samples_path("nope.json")


def test_figure6_gives_the_papers_ten_stages():
    found = stages(load_recipe(samples_path("figure6.json")))
    assert [(s.label, s.first, s.last, s.title) for s in found] == [
        ("a", 0, 13, "14 drops"),  # the centre's ring, one drop in each corner
        ("b", 14, 17, "4 drops"),  # the corners' second round
        ("c", 18, 21, "4 drops"),  # and third
        *((label, k, k, "comb") for label, k in zip("defghi", range(22, 28), strict=True)),
        ("j", 28, 28, "wave"),
    ]
    assert [s.time for s in found][:4] == [3.65, 4.65, 5.65, 7.4]


def drop(x, start=None, end=None, y=50):
    op = {"type": "drop", "center": [x, y], "radius": 5, "color": "#112233"}
    return {**op, "start": start, "end": end} if start is not None else op


def comb(start=None, end=None):
    op = {"type": "comb", "point": [0, 0], "angle": 0, "spacing": 20, "alpha": 9, "lambda": 4}
    return {**op, "start": start, "end": end} if start is not None else op


def recipe(*ops):
    return parse_recipe({"canvas": [100, 100], "ops": list(ops)})


def test_a_pause_or_end_to_start_opens_a_stage_and_overlap_does_not():
    assert spans(recipe(comb(0, 1), comb(0.5, 2), comb(2, 3), comb(3.5, 4))) == [
        ("a", 0, 1),
        ("b", 2, 2),
        ("c", 3, 3),
    ]


def test_ink_after_deforming_opens_a_stage_even_while_overlapping():
    assert spans(recipe(drop(10, 0, 2), comb(1, 3), drop(20, 2.5, 4))) == [
        ("a", 0, 0),
        ("b", 1, 1),
        ("c", 2, 2),
    ]


def test_a_round_of_drops_ends_when_the_dropper_comes_back():
    rounds = [drop(x, 0.2 * i, 0.2 * i + 0.5) for i, x in enumerate([50, 50, 50, 10, 90, 10, 90])]
    assert spans(recipe(*rounds)) == [("a", 0, 4), ("b", 5, 6)]


def test_ops_without_times_follow_one_another():
    found = stages(recipe(drop(50), comb(), comb()))
    assert [(s.first, s.last, s.time) for s in found] == [(0, 0, 0.0), (1, 1, 0.0), (2, 2, 0.0)]
    assert stages(recipe()) == []


def test_a_stage_shows_its_ops_complete_and_none_later(renderer):
    """Stage (a) of Figure 6 ends while stage (b)'s first drop is pouring: its
    picture is the first 14 ops alone, not the process at that time."""
    full = load_recipe(samples_path("figure6.json"))
    a = stages(full)[0]
    staged = Marbler(upto(full, a), renderer=renderer).render(None, a.time, (64, 64))
    doc = json.loads(samples_path("figure6.json").read_text())
    first = parse_recipe({**doc, "ops": doc["ops"][:14]})
    alone = Marbler(first, renderer=renderer).render(None, a.time, (64, 64))
    process = Marbler(full, renderer=renderer).render(None, a.time, (64, 64))
    assert np.array_equal(staged, alone)
    assert not np.array_equal(staged, process)


def test_strip_lays_out_the_stages_in_rows(renderer):
    three = recipe(drop(50, 0, 1), comb(1, 2), comb(2, 3))
    sheet = strip(three, 20, columns=2, marbler=Marbler(three, renderer=renderer))
    assert sheet.shape == (2 * (20 + 22 + 6) + 6, 2 * (20 + 6) + 6, 3)


def gallery(*args, cwd):
    return subprocess.run(
        [sys.executable, "-m", "marblevideo.gallery", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        env=subprocess_env(),
    )


def test_gallery_command_writes_the_figure6_strip(tmp_path):
    proc = gallery("-o", "steps.png", "--size", "24", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    sheet = cv2.imread(str(tmp_path / "steps.png"))
    assert sheet.shape == (2 * (24 + 28) + 6, 5 * (24 + 6) + 6, 3)


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["--ops", "missing.json", "-o", "s.png"], "cannot read recipe missing.json"),
        (["-o", "s.mp4"], "s.mp4: give an image output"),
        (["-o", "s.png", "--size", "0"], "--size: must be 1..4096"),
        (["-o", "s.png", "--size", "big"], "invalid int value"),
        (["--ops"], "expected one argument"),
        (["-o", "exists.png"], "exists.png: already exists; use -y"),
    ],
)
def test_gallery_mistakes_are_one_line_and_exit_2(tmp_path, args, says):
    (tmp_path / "exists.png").write_bytes(b"keep")
    proc = gallery(*args, cwd=tmp_path)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    (line,) = proc.stderr.splitlines()
    assert line.startswith("python -m marblevideo.gallery: ") and says in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["exists.png"]
    assert (tmp_path / "exists.png").read_bytes() == b"keep"
