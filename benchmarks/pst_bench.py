"""pst-stir: Jaffer's Wreath and Curl imported from tests/data/pst (their stirs in the
revision-4 form, ``turn``: one exponential a ring, each its own fall-off) beside the
same designs with each stir in the revision-2 form (``alpha`` = turn * pi / 180 *
mean |r|, ``falloff`` = L * mean |r|: the closed-form series where it applies),
1024x1024 blank-sheet frames, RGSS, ms per frame (median of 21, interleaved)."""

from __future__ import annotations

import math
import statistics
import time

from marblevideo.opencl.renderer import Renderer
from marblevideo.pstmarble import import_design
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry

from .common import ROOT

DESIGNS = ("wreath", "curl")


def alpha_form(op: dict) -> dict:
    """A turn-form stir as the alpha form of about the same reach."""
    if op["type"] != "stir":
        return op
    mean = sum(abs(r) for r in op["radii"]) / len(op["radii"])
    rest = {k: v for k, v in op.items() if k not in ("turn", "falloff")}
    return {**rest, "alpha": op["turn"] * math.pi / 180 * mean, "falloff": op["falloff"] * mean}


def interleaved(fns, repeat: int = 21, warmup: int = 3) -> list[float]:
    """The median seconds of each of ``fns``, run in turn so that all meet the
    machine's same phases."""
    for fn in fns * warmup:
        fn()
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(repeat):
        for k, fn in enumerate(fns):
            t = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - t)
    return [statistics.median(t) for t in times]


def pst_stir_part(device: str | None) -> None:
    renderer = Renderer(device)
    print(f"\n## pst-marble's stir (turn) against the revision-2 stir, on {renderer.info.name}")
    print("| design (1024x1024, rgss) | stirs | turn form ms | alpha form ms | ratio |")
    print("|---|---|---|---|---|")
    for name in DESIGNS:
        doc = import_design(ROOT / "tests" / "data" / "pst" / f"{name}.tex")
        forms = [doc, {**doc, "ops": [alpha_form(op) for op in doc["ops"]]}]
        specs = []
        for form in forms:
            recipe = parse_recipe({**form, "antialias": "rgss"}, name)
            specs.append(recipe.at(recipe.end_time()))
        geom = geometry(recipe.canvas, (1024, 1024))
        medians = interleaved(
            [lambda s=spec, g=geom: renderer.render(s, g, None) for spec in specs]
        )
        stirs = sum(op["type"] == "stir" for op in doc["ops"])
        ratio = medians[0] / medians[1]
        print(
            f"| {name} | {stirs} | {medians[0] * 1e3:.1f} | {medians[1] * 1e3:.1f} | {ratio:.2f} |"
        )
