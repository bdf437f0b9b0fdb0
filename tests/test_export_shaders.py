"""`marblevideo export` to shaders, run by the real hosts: the .frag by GStreamer's
glshader (GLSL 3.30 under Xvfb on Mesa's llvmpipe) over PNG frames and as a
generator; the ISF file compiled by glslangValidator inside the GL 3.3 and GL ES 3.0
preludes an ISF host inserts, and drawn by glshader with ISF's built-ins mapped
onto its uniforms. Every frame against the NumPy reference at its time."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from gl_hosts import (
    ISF_ON_GLSHADER,
    ISF_PRELUDES,
    glshader,
    glslang,
    isf_in_prelude,
    isf_parts,
    isf_uniforms,
    missing,
    shadertoy_in_prelude,
    write_frames,
)
from recipes import make_image, random_recipe

from marblevideo import reference
from marblevideo.bundled import preset_path
from marblevideo.cli import main
from marblevideo.recipe.frame import geometry
from marblevideo.recipe.load import parse_recipe

pytestmark = [
    pytest.mark.tier("integration"),
    pytest.mark.skipif(
        missing() is not None and not os.environ.get("CI"), reason=f"needs {missing()}"
    ),
]

#: A shader's frames against the reference: this share of pixels within LEVELS.
LEVELS, SHARE = 8, 0.98
#: Frames a case draws, at this rate (the export samples the recipe at it too).
FRAMES, FPS = 3, 2


def export(recipe: dict, folder: Path, suffix: str, *options: str) -> Path:
    src, out = folder / "recipe.json", folder / f"recipe{suffix}"
    src.write_text(json.dumps(recipe))
    argv = ["export", str(src), "-o", str(out), "--fps", str(FPS), "-q", "-y", *options]
    assert main(argv) == 0
    return out


def expected(recipe: dict, size, pictures=None, start: float = 0.0) -> list[np.ndarray]:
    r = parse_recipe(recipe)
    w, h = size
    canvas = r.canvas or (w, h)
    out = []
    for k in range(FRAMES):
        picture = None if pictures is None else pictures[k]
        geom = geometry(canvas, size, None if picture is None else size)
        frame = reference.render(r.at(start + k / FPS, canvas), geom, picture)
        out.append(frame if picture is not None else frame[..., :3])
    return out


def assert_agrees(got, want) -> None:
    for k, (g, w) in enumerate(zip(got, want, strict=True)):
        g = g[..., : w.shape[2]]
        share = float((np.abs(g.astype(int) - w.astype(int)).max(axis=2) <= LEVELS).mean())
        assert share >= SHARE, f"frame {k}: {share:.2%} of pixels within {LEVELS} levels"


def over_frames(recipe: dict, folder: Path, size=(64, 48)):
    frag = export(recipe, folder, ".frag")
    pictures = [make_image(*size, seed=k) for k in range(FRAMES)]
    inputs = write_frames(folder / "in", pictures)
    vertex = frag.with_suffix(".vert").read_text()
    got = glshader(frag.read_text(), folder, size, FRAMES, FPS, inputs, vertex=vertex)
    return got, expected(recipe, size, pictures)


@pytest.mark.parametrize("seed", [2, 9])
def test_random_recipes_through_glshader(tmp_path, seed):
    """Random recipes of every op type (keyed, eased, started and ended, each seed
    another pattern and edges mode) over PNG frames, time from the buffers."""
    assert_agrees(*over_frames(random_recipe(seed, 160, 120), tmp_path))


def test_a_sheet_through_glshader_with_strokes(tmp_path):
    """--sheet: a generator (its input ignored): drops, a stroke drawn in time and a
    keyed background."""
    recipe = {
        "marblevideo": 1,
        "canvas": [120, 80],
        "background": {"keys": [{"t": 0, "v": "#203040"}, {"t": 1, "v": "#e0c080"}]},
        "ops": [
            {"type": "drop", "center": [60, 40], "radius": 30, "color": "#c03020"},
            {
                "type": "stroke",
                "points": [[10, 20], [60, 50], [110, 30]],
                "times": [0, 0.5, 1],
                "width": 12,
            },
        ],
    }
    frag = export(recipe, tmp_path, ".frag", "--sheet")
    got = glshader(frag.read_text(), tmp_path, (90, 60), FRAMES, FPS)
    assert_agrees(got, expected(recipe, (90, 60)))


def isf_on_glshader(fs: Path) -> str:
    header, body = isf_parts(fs.read_text())
    declared = isf_uniforms({"INPUTS": [i for i in header["INPUTS"] if i["TYPE"] != "image"]})
    return ISF_ON_GLSHADER + declared + body


def test_nonpareil_as_an_isf_generator_and_a_frag(tmp_path):
    """The bundled nonpareil (143 ops after its layouts: the loop walk) as an ISF
    generator at offset 3 s and as a .frag generator, each drawn by glshader: both
    as the reference draws it."""
    recipe = json.loads(preset_path("nonpareil").read_text())
    fs = export(recipe, tmp_path, ".fs", "--sheet")
    uniforms = "speed=(float)1.0, offset=(float)3.0, loop=(boolean)false"
    (tmp_path / "isf").mkdir()
    got = glshader(isf_on_glshader(fs), tmp_path / "isf", (72, 48), FRAMES, FPS, uniforms=uniforms)
    assert_agrees(got, expected(recipe, (72, 48), start=3.0))
    frag = export(recipe, tmp_path, ".frag", "--sheet")
    (tmp_path / "frag").mkdir()
    got = glshader(frag.read_text(), tmp_path / "frag", (72, 48), FRAMES, FPS)
    assert_agrees(got, expected(recipe, (72, 48)))


def test_isf_files_compile_in_each_hosts_prelude(tmp_path):
    """Filters and generators of random recipes and presets: the body (no #version)
    compiles inside GLSL 3.30's and GLSL ES 3.00's preludes."""
    cases = [(random_recipe(s, 160, 120), sheet) for s, sheet in ((1, False), (6, True))]
    cases += [(json.loads(preset_path(n).read_text()), True) for n in ("bouquet", "tulip")]
    for k, (recipe, sheet) in enumerate(cases):
        fs = export(recipe, tmp_path, ".fs", *(["--sheet"] if sheet else []))
        header, body = isf_parts(fs.read_text())
        assert "#version" not in body
        names = [i["NAME"] for i in header["INPUTS"]]
        assert names[: 1 - sheet] == ([] if sheet else ["inputImage"])
        assert {"speed", "offset", "loop"} <= set(names)
        for profile in ISF_PRELUDES:
            done = glslang(isf_in_prelude(fs.read_text(), profile), tmp_path, f"c{k}")
            assert done.returncode == 0, (profile, done.stdout[-1500:])


def test_shadertoy_code_compiles_in_its_prelude(tmp_path):
    """--to shadertoy, a filter and a generator: the code compiles inside the GLSL
    ES 3.00 prelude and main Shadertoy puts around the Image tab."""
    for k, (name, options) in enumerate([("swirl", ()), ("nonpareil", ("--sheet",))]):
        out = tmp_path / f"{name}.glsl"
        argv = ["export", name, "-o", str(out), "--to", "shadertoy", "-q", *options]
        assert main(argv) == 0
        text = out.read_text()
        assert "void mainImage(out vec4 fragColor, in vec2 fragCoord)" in text
        done = glslang(shadertoy_in_prelude(text), tmp_path, f"s{k}")
        assert done.returncode == 0, done.stdout[-1500:]


def test_an_isf_filter_follows_time_speed_and_offset(tmp_path):
    """An ISF filter over frames: with speed 0.5 and offset 1 s, frame k shows the
    recipe at 1 + k / (2 FPS) (sampled at 2 FPS: every frame's time a sample)."""
    recipe = random_recipe(12, 160, 120)
    fs = export(recipe, tmp_path, ".fs", "--fps", str(2 * FPS))
    pictures = [make_image(64, 48, seed=k) for k in range(FRAMES)]
    inputs = write_frames(tmp_path / "in", pictures)
    uniforms = "speed=(float)0.5, offset=(float)1.0, loop=(boolean)false"
    got = glshader(isf_on_glshader(fs), tmp_path, (64, 48), FRAMES, FPS, inputs, uniforms)
    r = parse_recipe(recipe)
    geom = geometry(r.canvas, (64, 48), (64, 48))
    want = [reference.render(r.at(1 + 0.5 * k / FPS), geom, pictures[k]) for k in range(FRAMES)]
    assert_agrees(got, want)


def test_shader_refusals_and_safety(tmp_path, capsys):
    """What a shader cannot carry: one line, exit 2, nothing written; a recipe's text
    never reaches the file, and the .frag holds no double quote (gst-launch-1.0
    takes it as a quoted property value)."""
    out = tmp_path / "x.frag"
    for argv, text in [
        (["export", "dance", "-o", str(out)], "motion: camera motion"),
        (["export", "pulse", "-o", str(tmp_path / "x.fs")], "follows a signal"),
        (["export", "swirl", "-o", str(out), "--constant-memory", "70000"], "only for .cl"),
    ]:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and text in err[0], err
    assert list(tmp_path.iterdir()) == []
    recipe = random_recipe(3, 160, 120)
    recipe["description"] = '" */ uniform float evil_q7z; /* "'
    for suffix in (".frag", ".fs"):
        text = export(recipe, tmp_path, suffix).read_text()
        assert "q7z" not in text
    assert '"' not in (tmp_path / "recipe.frag").read_text()
    assert (tmp_path / "recipe.vert").read_text().startswith("#version 330")
