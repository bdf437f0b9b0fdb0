"""Hostile recipes through every export: huge numbers, strings shaped like code,
thousands of ops. Each is refused in one line (exit 2, nothing written) or
exported as a file that builds (the .cl on the test device's OpenCL, the shaders
in glslangValidator) and holds none of the recipe's text (Hypothesis, seeded)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess

import numpy as np
import pytest
from gl_hosts import isf_in_prelude, shadertoy_in_prelude
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from recipes import random_recipe

from marblevideo.cli import main
from marblevideo.limits import NUMBER_LIMIT

pytestmark = [
    pytest.mark.tier("integration"),
    pytest.mark.skipif(
        shutil.which("glslangValidator") is None and not os.environ.get("CI"),
        reason="needs glslangValidator",
    ),
]

CODE = '*/ #include "x_q7z" } __kernel void evil_q7z() { /* " \\ %s'


def _scaled(value, factor):
    if isinstance(value, bool) or not isinstance(value, int | float):
        return value
    return float(np.clip(value * factor, -NUMBER_LIMIT, NUMBER_LIMIT))


def _walk(node, factor):
    if isinstance(node, dict):
        return {k: v if k in ("type", "marblevideo") else _walk(v, factor) for k, v in node.items()}
    if isinstance(node, list):
        return [_walk(v, factor) for v in node]
    return _scaled(node, factor)


@st.composite
def hostile_recipes(draw):
    recipe = random_recipe(draw(st.integers(0, 10_000)), 160, 120)
    if draw(st.booleans()):
        recipe = _walk(recipe, draw(st.sampled_from([1e-30, 1e6, 1e20, 1e29, -1e29])))
    copies = draw(st.sampled_from([1, 1, 50, 2000]))
    recipe["ops"] = (recipe["ops"] * copies)[: 4 * copies + len(recipe["ops"])]
    recipe["description"] = CODE
    return recipe


def _compile_cl(renderer, text: str) -> None:
    import pyopencl as cl

    cl.Program(renderer.context, text).build(options=["-w"])


@settings(max_examples=12, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(recipe=hostile_recipes(), fmt=st.sampled_from([".cl", ".frag", ".fs", "shadertoy"]))
def test_hostile_recipes_export_or_are_refused(tmp_path_factory, capsys, renderer, recipe, fmt):
    folder = tmp_path_factory.mktemp("hostile")
    src = folder / "recipe.json"
    src.write_text(json.dumps(recipe))
    out = folder / ("out.glsl" if fmt == "shadertoy" else f"out{fmt}")
    argv = ["export", str(src), "-o", str(out), "-q"]
    argv += ["--to", "shadertoy"] if fmt == "shadertoy" else []
    status = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    if status != 0:
        assert status == 2 and len(err) == 1 and err[0].startswith("marblevideo: "), err
        assert sorted(p.name for p in folder.iterdir()) == ["recipe.json"]
        return
    text = out.read_text()
    assert "q7z" not in text
    if fmt == ".cl":
        _compile_cl(renderer, text)
        return
    if fmt == ".fs":
        text = isf_in_prelude(text, "300 es")
    elif fmt == "shadertoy":
        text = shadertoy_in_prelude(text)
    path = folder / "check.frag"
    path.write_text(text)
    done = subprocess.run(["glslangValidator", str(path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-1500:]
