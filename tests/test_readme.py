"""The README's Python example runs as written (from the repository root), and
so does every marblevideo command of the ```sh blocks of README.md and
docs/*.md, made small and quick (except the few in :data:`SKIPPED`)."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import ROOT, subprocess_env
from live_helpers import LiveProcess

from marblevideo import load_recipe

pytestmark = pytest.mark.tier("integration")


def test_readme_python_example_runs(monkeypatch, capsys, tmp_path):
    """The example as a user runs it from the checkout, in a folder of its own
    (the samples linked in), so that the test writes nothing into the checkout."""
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks, "README has a Python example"
    (tmp_path / "samples").symlink_to(ROOT / "samples")
    monkeypatch.chdir(tmp_path)
    os.makedirs("out", exist_ok=True)
    exec(compile(blocks[0], "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "frames, copy audio" in out
    assert (tmp_path / "out" / "api-demo.mp4").stat().st_size > 0


# ---------------------------------------------------------------------------- the ```sh commands

#: README commands that cannot run in a test, with the reason; every other
#: `marblevideo ...` or `python -m marblevideo...` line of a ```sh block runs
SKIPPED = {
    "marblevideo live 0 --ops samples/swirl.json --preview --vcam": (
        "needs camera 0 and a v4l2loopback virtual camera"
    ),
    "marblevideo midi": "needs a MIDI system (ALSA's sequencer, /dev/snd/seq)",
    "marblevideo live 0 --ops dance --preview": (
        "needs camera 0 (tests/test_live_motion.py runs the motion over a file source)"
    ),
    "marblevideo devices --check": (
        "the device self-test (a minute of kernel builds on a cold cache): "
        "tests/test_selfcheck.py runs this very command and checks its report"
    ),
    "marblevideo live 0 --ops my.json --preview --midi nanoKONTROL2": (
        "needs camera 0 and a MIDI controller (tests/test_controllers.py maps MIDI messages)"
    ),
    "marblevideo samples/coffee.mp4 --ops samples/swirl.json -o "
    "rtmp://127.0.0.1:1935/live/KEY --realtime": (
        "a stream at the clip's pace: tests/test_live_stream.py plays clips to nginx-rtmp"
    ),
    "marblevideo samples/coffee.mp4 --ops take.json -o replay.mp4": (
        "renders the take the command before writes (tests/test_live_controllers.py does both)"
    ),
    "marblevideo dancer.mp4 --ops dance -o danced.mp4 --automation danced-take.json": (
        "a clip of a dancer; tests/test_motion_files.py renders motion over a moving disc "
        "and writes its take"
    ),
    "marblevideo dancer.mp4 --ops danced-take.json -o again.mp4": (
        "renders the take the command before writes (tests/test_motion_files.py does both)"
    ),
    "marblevideo --ops wreath-video.json -o wreath.mp4 --size 480x480": (
        "renders the recipe the command before imports (tests/test_pst_import.py does both)"
    ),
}
VIDEO_EXTENSIONS = (".mp4", ".mov", ".mkv", ".webm", ".gif", ".apng", ".nut")
#: Commands that print (to stdout) instead of writing an output file.
PRINTING = (["devices"], ["schema"], ["presets"], ["ops"])
#: Commands that write a file but take no --size.
SIZELESS = (["import"], ["export"])
SMALL = 64  # the longest side of any output


def readme_commands() -> list[str]:
    """Every command of the ```sh blocks of README.md and docs/*.md that runs
    marblevideo (``marblevideo ...``, ``python -m marblevideo[.x] ...``), comment dropped."""
    found = []
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for block in re.findall(r"```sh\n(.*?)```", doc.read_text(), re.S):
            for line in block.replace("\\\n", " ").splitlines():
                words = shlex.split(line, comments=True)
                program = words[0] if words[:1] == ["marblevideo"] else None
                if words[:2] == ["python", "-m"] and len(words) > 2:
                    program = words[2]
                if program and program.split(".")[0] == "marblevideo":
                    found.append(shlex.join(words))
    return list(dict.fromkeys(found))


def setting(words: list[str], option: str, value: str) -> list[str]:
    if option in words:
        words[words.index(option) + 1] = value
        return words
    return [*words, option, value]


def small_size(text: str | None) -> str:
    """A WxH (default square) scaled so its longest side is :data:`SMALL`, even sides."""
    w, h = (int(v) for v in (text or "1x1").lower().split("x"))
    scale = SMALL / max(w, h)
    return f"{max(2, round(w * scale / 2) * 2)}x{max(2, round(h * scale / 2) * 2)}"


def redirected(command: str) -> tuple[str, str | None, str | None]:
    """The command without its final ``> FILE`` and ``< FILE``, and those FILEs
    (standard output's, standard input's; None without one)."""
    words = shlex.split(command)
    found = {">": None, "<": None}
    while len(words) > 2 and words[-2] in found:
        found[words[-2]] = words[-1]
        words = words[:-2]
    return shlex.join(words), found[">"], found["<"]


def sequence_inputs(argv: list[str], folder: Path) -> None:
    """Make the image sequence a command reads (``name_%04d.png``): three frames
    of samples/coffee.jpg, as an earlier command of the README would have."""
    import cv2

    from marblevideo.media.formats import is_sequence, sequence_name

    if len(argv) > 3 and is_sequence(argv[3]):
        image = cv2.imread(str(ROOT / "samples" / "coffee.jpg"))
        for number in (1, 2, 3):
            cv2.imwrite(str(folder / sequence_name(argv[3], number)), image)


def written(folder: Path, name: str) -> Path:
    """The file an ``-o name`` wrote (a sequence's first frame)."""
    from marblevideo.media.formats import is_sequence, sequence_name

    return folder / (sequence_name(name, 1) if is_sequence(name) else name)


def quick(command: str) -> list[str]:
    """The command made quick: small outputs, short videos (whole with --cluster,
    which cuts none), live and design runs of one second (no browser)."""
    words = shlex.split(command)
    if words[0] == "marblevideo":
        words = ["python", "-m", "marblevideo", *words[1:]]
    module, args = words[2], words[3:]
    if module == "marblevideo.gallery":
        args = setting(args, "--size", "24")
    elif args[:1] in (["live"], ["design"]):
        args = setting(args, "--duration", "1")
        if "--preview" in args or args[0] == "design":
            args = setting(args, "--port", "0")  # any free port
        if args[0] == "design" and "--no-browser" not in args:
            args.append("--no-browser")
        if args[1] == "test":
            args = setting(args, "--size", "64x48")
    elif args[:1] not in PRINTING and args[:1] not in SIZELESS:
        size = args[args.index("--size") + 1] if "--size" in args else None
        if "--uv" not in args:  # a UV pass sets its own (small) size
            args = setting(args, "--size", small_size(size))
        if Path(args[args.index("-o") + 1]).suffix in VIDEO_EXTENSIONS and "--cluster" not in args:
            video_in = args[0].endswith(VIDEO_EXTENSIONS) or "%" in args[0]
            args = setting(args, "--end" if video_in else "--duration", "0.3")
    return [sys.executable, "-m", module, *args]


def test_every_skipped_command_is_still_in_the_readme():
    assert set(SKIPPED) <= set(readme_commands())


@pytest.mark.parametrize("command", readme_commands())
def test_readme_command_runs(command, tmp_path):
    """Run from a folder with the samples at the README's relative paths."""
    if command in SKIPPED:
        pytest.skip(SKIPPED[command])
    (tmp_path / "samples").symlink_to(ROOT / "samples")
    command, target, source = redirected(command)
    argv = quick(command)
    sequence_inputs(argv, tmp_path)
    proc = subprocess.run(
        argv,
        cwd=tmp_path,
        input=(tmp_path / source).read_bytes() if source else None,
        capture_output=True,
        timeout=120,
        env=subprocess_env(),
    )
    stderr = proc.stderr.decode(errors="replace")
    assert proc.returncode == 0, f"{shlex.join(argv[2:])}: {stderr}"
    if argv[3:4] == ["batch"]:  # a template: some output of it
        pattern = re.sub(r"\{[^}]*\}", "*", argv[argv.index("-o") + 1])
        assert any(p.stat().st_size > 0 for p in tmp_path.glob(pattern))
    elif "-o" in argv and argv[argv.index("-o") + 1] != "-":
        assert written(tmp_path, argv[argv.index("-o") + 1]).stat().st_size > 0
    if argv[3:4] in PRINTING:
        assert proc.stdout.strip()
    if target is not None:  # what the shell would write; a recipe must load
        (tmp_path / target).write_bytes(proc.stdout)
        assert proc.stdout
        if target.endswith(".json") and argv[3:4] == ["presets"]:
            load_recipe(tmp_path / target)


def test_readme_designer_api_example_drives_a_designer(tmp_path):
    """The README's second Python block, against a real `marblevideo design` on its
    default port: the drop it adds is in the saved recipe file."""
    text = (ROOT / "README.md").read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "/api/recipe" in b)
    recipe = tmp_path / "design.json"
    designer = LiveProcess("--ops", recipe, "--no-browser", cwd=tmp_path, command="design")
    try:
        assert designer.url.startswith("http://127.0.0.1:8765/")  # the port the block uses
        exec(compile(block, "README.md", "exec"), {})
        ops = json.loads(recipe.read_text())["ops"]
        assert ops[-1]["type"] == "drop" and ops[-1]["center"] == [512, 384]
    finally:
        assert designer.stop() == 0, designer.stderr()
