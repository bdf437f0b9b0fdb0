"""Fuzzing the ways in that are not a recipe file (tests/test_fuzz_recipes.py has
those): the pst-marble importer on generated .tex/.pst text, and the command
line's argument lists run in this process (``cli.main``). The property is the
same everywhere: a clean result, or a MarbleError (in process) / exit 1 or 2 with
one line naming the file; never another exception, never more memory or time
than the limits (RLIMIT_AS: what the process holds plus 1 GiB; seconds per
input), and nothing written but the named output.

Hypothesis runs derandomized (conftest's ``ci`` profile: a fixed seed, no
database), so a failure replays; ``HYPOTHESIS_PROFILE=dev`` explores afresh. The
inputs found interesting (each once a finding, now fixed) are kept in
tests/data/fuzz/ and replayed by :func:`test_the_corpus_replays`.
"""

from __future__ import annotations

import contextlib
import json
import re
import resource
import shutil
import signal
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers import files, one_line, run_main
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from marblevideo.errors import MarbleError, UsageError
from marblevideo.pstmarble import import_design
from marblevideo.pstmarble.actions import ACTIONS, HELPERS, REFUSED, SPRAYS
from marblevideo.pstmarble.postscript import CONSTANTS, OPERATORS, STACK_WORDS

pytestmark = pytest.mark.tier("integration")

CORPUS = Path(__file__).resolve().parent / "data" / "fuzz"
#: Seconds one input may take (a render's first program build included).
PER_INPUT = 60
FUZZ = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])


class TooSlow(BaseException):
    """An input over PER_INPUT seconds (a BaseException: no handler in the code
    under test takes it for its own)."""


@contextlib.contextmanager
def bounded(seconds: float = PER_INPUT, extra: int = 1 << 30):
    """The block under a time limit (SIGALRM) and an address-space limit of what
    the process holds now plus ``extra`` bytes (a runaway is a MemoryError)."""
    status = Path("/proc/self/status").read_text()
    held = int(re.search(r"VmSize:\s*(\d+)", status).group(1)) * 1024
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = held + extra if hard == resource.RLIM_INFINITY else min(held + extra, hard)

    def alarm(signum, frame):
        raise TooSlow(f"over {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
        signal.signal(signal.SIGALRM, previous)


# ---------------------------------------------------------------------------- the importer

NUMBERS = st.one_of(
    st.integers(-20, 1200).map(str),
    st.sampled_from(["0", "1", "0.5", "-3", "257", "4097", "100000", "1e9", "1e308", "-1e308",
                     "1e999", "1e-300", ".5", "+2", "1e30", "2e5"]),
    st.floats(allow_nan=False, allow_infinity=False).map(repr),
)  # fmt: skip
NAMES = sorted(
    {*ACTIONS, *SPRAYS, *HELPERS, *REFUSED, *OPERATORS, *STACK_WORDS, *CONSTANTS, "colors"}
)
OTHERS = ["[", "]", "{", "}", "(ff0000)", "(1d3557)", "(zz)", "()", "(", ")", "/x", "x",
          "/f", "f", "def", "%c\n", "\\relax", "[1 0 0]", "[0.2 0.5 0.9]",
          "[ 5 40 0 tines ]"]  # fmt: skip
TOKENS = st.one_of(NUMBERS, st.sampled_from(NAMES), st.sampled_from(OTHERS))


#: Each action with its arguments: N a number, C colours, A an array of numbers.
TEMPLATES = {
    "drop": "N N N C", "concentric-rings": "N N N C N", "line-drops": "N N N A C N",
    "serpentine-drops": "N N A A N C N", "coil-drops": "N N N N N N C N N",
    "normal-drops": "N N N N N C N N", "uniform-drops": "N N N N N C N N",
    "Gaussian-drops": "N N N N N C N N", "rake": "N A N N N", "stir": "N N A N N N",
    "vortex": "N N N N", "jiggle": "N N N N N", "wiggle": "N N N N", "shift": "N N",
    "turn": "N N N", "stylus": "N N N N N N", "normal-spray": "N N N N N C N N",
    "uniform-spray": "N N N N N C N N",
}  # fmt: skip
PLAIN = st.integers(1, 600).map(str)
#: Mostly plain numbers (so that many designs import), one in eight hostile.
MOSTLY = st.integers(0, 7).flatmap(lambda k: NUMBERS if k == 0 else PLAIN)
COLOURS = st.sampled_from(["colors", "(ff0000)", "[1 0 0]", "[0.2 0.5 0.9]", "(1d3557) 0.5 tint",
                           "[ [1 0 0] [0 0 1] ]", "[0 0.4 0.2] -1 shade", "(zz)",
                           "[1 2]"])  # fmt: skip


@st.composite
def calls(draw, numbers=MOSTLY, names=tuple(TEMPLATES)):
    """An action with its arguments, mostly plain numbers (so that many import), at
    times one hostile (huge, non-finite, negative), a colour or an array."""
    name = draw(st.sampled_from(sorted(names)))
    arrays = st.one_of(
        st.lists(numbers, min_size=1, max_size=5).map(lambda v: f"[ {' '.join(v)} ]"),
        st.tuples(numbers, numbers).map(lambda t: f"[ {t[0]} {t[1]} 0 tines ]"),
    )
    parts = {"N": numbers, "C": COLOURS, "A": arrays}
    args = [draw(parts[kind]) for kind in TEMPLATES[name].split()]
    return " ".join([*args, name])


PROGRAMS = st.recursive(
    st.lists(st.integers(0, 5).flatmap(lambda k: TOKENS if k == 0 else calls()), max_size=8).map(
        " ".join
    ),
    lambda inner: st.one_of(
        st.tuples(NUMBERS, inner).map(lambda t: f"{t[0]} {{ {t[1]} }} repeat"),
        st.tuples(NUMBERS, NUMBERS, NUMBERS, inner).map(
            lambda t: f"{t[0]} {t[1]} {t[2]} {{ pop {t[3]} }} for"
        ),
        st.tuples(inner, inner).map(lambda t: f"/f {{ {t[0]} }} def {t[1]} f"),
        st.lists(inner, max_size=3).map(" ".join),
        inner.map(lambda p: f"[ {p} ]"),
    ),
    max_leaves=12,
)
OPTIONS = ["overscan", "viscosity", "colors", "background", "seed", "spractions", "shadings"]


@st.composite
def plain_designs(draw) -> str:
    """A \\psMarble of well-formed actions of plain numbers: most import."""
    names = sorted(set(TEMPLATES) - set(SPRAYS))
    actions = " ".join(draw(st.lists(calls(PLAIN, names), min_size=1, max_size=5)))
    return f"\\psMarble[actions={{{actions}}}]({draw(PLAIN)},{draw(PLAIN)})"


@st.composite
def designs(draw) -> str:
    """A design's text: a plain list of actions, a \\psMarble with options and a
    size, in a LaTeX document or not, braces balanced or not."""
    actions = draw(PROGRAMS)
    kind = draw(
        st.sampled_from(["plain", "marble", "marble", "marble", "document", "psset", "raw"])
    )
    if kind == "plain":
        return actions
    if kind == "raw":
        return " ".join(draw(st.lists(st.one_of(TOKENS, st.sampled_from(
            ["\\psMarble", "[", "]", "(10,10)", "(0,0)(5,5)", "=", ",", "actions", "{", "}"]
        )), max_size=20)))  # fmt: skip
    options = [f"actions={{{actions}}}"]
    for key in draw(st.lists(st.sampled_from(OPTIONS), max_size=3, unique=True)):
        value = draw(calls()) if key == "spractions" else draw(st.one_of(PLAIN, COLOURS, PROGRAMS))
        options.append(f"{key}={{{value}}}")
    w, h = draw(MOSTLY), draw(MOSTLY)
    size = draw(st.sampled_from([f"({w},{h})"] * 5 + [f"(0,0)({w},{h})", f"({w})", ""]))
    marble = f"\\psMarble[{','.join(options)}]{size}"
    if kind == "psset":
        marble = f"\\psset[pst-marble]{{viscosity={draw(NUMBERS)}}}\n{marble}"
    if kind == "document":
        marble = f"\\documentclass{{article}}\n\\begin{{document}}\n{marble}\n\\end{{document}}\n"
    return marble


def import_or_refuse(path: Path) -> dict | None:
    """The property of one design file: the recipe, or one line naming the file."""
    began = time.monotonic()
    try:
        with bounded():
            doc = import_design(path)
    except UsageError as exc:
        text = str(exc)
        assert "\n" not in text and exc.exit_code == 2, text
        assert text.startswith(str(path)), text
        return None
    finally:
        assert time.monotonic() - began < PER_INPUT
    assert doc["ops"] and doc["marblevideo"] == 1
    return doc


@settings(FUZZ, max_examples=500)
@given(designs() | plain_designs())
def test_generated_designs_import_or_are_refused_in_one_line(tmp_path_factory, text):
    path = tmp_path_factory.getbasetemp() / "fuzz.tex"
    path.write_text(text)
    import_or_refuse(path)


@settings(FUZZ, max_examples=150)
@given(st.binary(max_size=200) | st.text(max_size=120).map(str.encode))
def test_arbitrary_bytes_import_or_are_refused(tmp_path_factory, data):
    path = tmp_path_factory.getbasetemp() / "fuzz.pst"
    path.write_bytes(data)
    import_or_refuse(path)


# ---------------------------------------------------------------------------- the command line

DROP = {"type": "drop", "center": [32, 24], "radius": 9, "color": "#2255aa"}
RECIPE = {"canvas": [64, 48], "antialias": "none", "ops": [DROP]}
LONG = {**RECIPE, "ops": [{**DROP, "start": 0, "end": 1e30}]}
#: The files each command line finds in its folder.
INPUTS = {
    "ok.json": json.dumps(RECIPE),
    "long.json": json.dumps(LONG),
    "bad.json": '{"ops": [{"type": "drop", "radius": -1}]}',
    "binary.json": b'{"\x96\x00\xff' + bytes(range(256)),
    "mine.tex": "\\psMarble[actions={0 0 100 (1d3557) drop}](10,10)\n",
    "big.tex": "\\psMarble[actions={0 [ 1e308 10 0 tines ] 40 200 20 rake}](10,10)\n",
    "empty.tex": "",
}
VALUES = {
    "--size": ["16x12", "16", "x12", "0x0", "-1x10", "99999x1", "abc", "1e308x1", "8x"],
    "--time": ["0", "0.5", "-1", "1e308", "nan", "inf", "abc", "-0"],
    "--duration": ["0.25", "0", "-1", "1e308", "nan", "inf", "1e-300"],
    "--fps": ["2", "0", "-5", "1e308", "nan", "1000.5", "4"],
    "--start": ["0", "-1", "1e308", "nan"],
    "--end": ["1", "-1", "1e308", "0"],
    "--fit": ["stretch", "crop", "pad", "bogus"],
    "--format": ["png", "jpeg", "mp4", "gif", "webp", "bogus", "y4m"],
    "--view": ["0,0,10,10", "-5,0,10,10", "0,0,0,0", "nan,0,1,1", "1e308,0,1,1", "a,b"],
    "--crf": ["23", "-1", "99999999999999999999", "abc"],
    "--codec": ["libx264", "bogus", "gif"],
    "--preset": ["fast", "bogus"],
    "--pix-fmt": ["yuv420p", "bogus", "rgb24"],
    "--encoder-opt": ["tune=film", "bogus", "=x", "crf=1e308"],
    "--audio": ["auto", "none", "aac", "bogus"],
    "--tolerance": ["0.05", "0", "-1", "1e308", "nan"],
    "--device": ["bogus", "7:7"],
    "--segments": ["2", "-1", "1e308"],
    "--jobs": ["1", "0", "abc"],
    "--soundtrack": ["missing.wav", "ok.json"],
    "--automation": ["take.json", "ok.json", "adir"],
    "--progress": ["off", "bogus"],
}
FLAGS = [
    "-y",
    "-q",
    "--exact-walk",
    "--bogus",
    "-z",
    "--",
    "",
    "--size=",
    "--ops=ok.json",
]  # no -: stdin
RECIPES = ["ok.json", "long.json", "bad.json", "binary.json", "missing.json",
           "samples/swirl.json", "swirl", "adir", "mine.tex"]  # fmt: skip
OUTPUTS = ["o.png", "o.jpg", "o.mp4", "o.gif", "o.webp", "adir", "o", "o.xyz", "missing/o.png",
           "ok.json", "o.json"]  # fmt: skip
SOURCES = ["img.png", "missing.png", "ok.json", "binary.json", "adir"]


@st.composite
def render_lines(draw) -> list[str]:
    """``[INPUT] --ops RECIPE -o OUTPUT`` with up to four options, some swapped,
    dropped or repeated, and stray words."""
    line = ["--ops", draw(st.sampled_from(RECIPES)), "-o", draw(st.sampled_from(OUTPUTS))]
    if draw(st.booleans()):
        line.insert(0, draw(st.sampled_from(SOURCES)))
    for flag in draw(st.lists(st.sampled_from(sorted(VALUES)), max_size=4)):
        line += [flag, draw(st.sampled_from(VALUES[flag]))]
    for _ in range(draw(st.integers(0, 2))):
        line.insert(draw(st.integers(0, len(line))), draw(st.sampled_from(FLAGS)))
    if draw(st.integers(0, 9)) == 0:
        del line[draw(st.integers(0, len(line) - 1))]
    return line


@st.composite
def other_lines(draw) -> list[str]:
    """The other commands that read input: import, presets, ops, schema."""
    command = draw(st.sampled_from(["import", "presets", "ops", "schema"]))
    words = {
        "import": ["mine.tex", "big.tex", "empty.tex", "missing.tex", "adir", "binary.json",
                   "-o", "o.json", "-o", "o.png", "-o", "-", "-o", "adir", "-y", "--animate",
                   "6", "--animate", "-1", "--animate", "1e308", "--animate", "nan"],
        "presets": ["swirl", "bogus", "--paths", "swirl.json", ""],
        "ops": ["vortex", "bogus", "stroke", ""],
        "schema": ["--bogus", "x"],
    }[command]  # fmt: skip
    line = [command, *draw(st.lists(st.sampled_from(words), max_size=6))]
    if command == "import" and draw(st.integers(0, 3)):  # mostly a whole command
        line += [draw(st.sampled_from(words[:6])), "-o", draw(st.sampled_from(OUTPUTS))]
    return line


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    """A folder holding INPUTS, a small image and an empty folder ``adir``."""
    path = tmp_path_factory.mktemp("lines")
    for name, content in INPUTS.items():
        if isinstance(content, bytes):
            (path / name).write_bytes(content)
        else:
            (path / name).write_text(content)
    cv2.imwrite(str(path / "img.png"), np.full((12, 16, 3), 90, np.uint8))
    (path / "adir").mkdir()
    return path


def outputs_named(line: list[str]) -> set[str]:
    """The files a command line names to write: -o's and --automation's."""
    named = set()
    for flag, value in zip(line, line[1:], strict=False):
        if flag in ("-o", "--output", "--automation"):
            named.add(Path(value).parts[0] if value else value)
    named |= {arg.split("=", 1)[1] for arg in line if arg.startswith(("-o=", "--output="))}
    return named


def run_or_refuse(folder: Path, line: list[str]) -> None:
    """The property of one command line: exit 0, or 1 or 2 with one line on
    stderr; nothing written but its named outputs (removed after)."""
    before = files(folder)
    with contextlib.chdir(folder):
        try:
            with bounded():
                proc = run_main(*line)
        except MarbleError as exc:  # pragma: no cover - main reports every one
            pytest.fail(f"{line}: {exc!r} escaped main")
    assert proc.returncode in (0, 1, 2), (line, proc.returncode, proc.stderr)
    if proc.returncode:
        one_line(proc)
    new = set(files(folder)) - set(before)
    assert new <= outputs_named(line), (line, new, proc.stderr)
    assert not list((folder / "adir").iterdir()), line
    for name in new:
        path = folder / name
        shutil.rmtree(path) if path.is_dir() else path.unlink()
    for name, content in INPUTS.items():  # an overwritten input (-y -o ok.json) put back
        data = content if isinstance(content, bytes) else content.encode()
        if (folder / name).read_bytes() != data:
            (folder / name).write_bytes(data)


@settings(FUZZ, max_examples=120)
@given(render_lines())
def test_render_command_lines_run_or_are_refused_in_one_line(folder, line):
    run_or_refuse(folder, line)


@settings(FUZZ, max_examples=120)
@given(other_lines())
def test_other_command_lines_run_or_are_refused_in_one_line(folder, line):
    run_or_refuse(folder, line)


# ---------------------------------------------------------------------------- the corpus


def corpus(kind: str) -> list[Path]:
    return sorted(CORPUS.glob(f"*.{kind}"))


@pytest.mark.parametrize("path", corpus("tex") + corpus("pst"), ids=lambda p: p.name)
def test_the_corpus_designs_replay(path):
    """Each design found once: refused in one line naming the file, or imported."""
    import_or_refuse(path)


@pytest.mark.parametrize("path", corpus("args"), ids=lambda p: p.name)
def test_the_corpus_command_lines_replay(folder, path):
    """Each command line found once (a JSON list of arguments, run in ``folder``)."""
    run_or_refuse(folder, json.loads(path.read_text()))
