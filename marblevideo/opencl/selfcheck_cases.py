"""The cases of the device self-test (:mod:`marblevideo.opencl.selfcheck`): small
recipes derived from the real lists (every op type's example, antialiasing
pattern and edges mode; a recipe longer than the unrolled walk; I420 routes),
and the deterministic input picture they are rendered over.

Conventions: canvas units as the op definitions' examples (:data:`CANVAS`);
pictures are RGBA uint8 (H, W, 4).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

from marblevideo.opencl.program import UNROLL_LIMIT
from marblevideo.ops import EXAMPLE_CANVAS, REGISTRY
from marblevideo.recipe.antialias import PATTERNS
from marblevideo.recipe.frame import EDGE_MODES

CANVAS = EXAMPLE_CANVAS  # the canvas the op definitions' examples are drawn for
INPUT_SIZE = (76, 56)  # even (I420), and not the output size (the input is scaled)


def input_picture(w: int = INPUT_SIZE[0], h: int = INPUT_SIZE[1]) -> np.ndarray:
    """A deterministic RGBA input with texture: waves, hard-edged rings, a fine
    hashed grain, and alpha falling from 255 to 128 across it."""
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    grain = ((xx * 7 + yy * 13) % 17) * 3.0
    r = 100 + 100 * np.sin(xx * 0.31) + grain
    g = 127.5 + 127.5 * np.cos(yy * 0.23 + xx * 0.05)
    b = 255.0 * ((np.hypot(xx - w / 2, yy - h / 2) / 5).astype(int) % 2)
    a = 255.0 - 127.0 * xx / max(w - 1, 1)
    rgba = np.stack([r, g, b, a], axis=2)
    return np.clip(np.floor(rgba + 0.5), 0, 255).astype(np.uint8)


def _op(kind: str) -> dict:
    """The op definition's own example (drawn for :data:`CANVAS`)."""
    return copy.deepcopy(dict(REGISTRY[kind].example))


def _recipe(ops: list[dict], antialias: str = "rgss", edges: str = "clamp") -> dict:
    return {
        "marblevideo": 1,
        "canvas": list(CANVAS),
        "background": "#f1faee",
        "antialias": antialias,
        "edges": edges,
        "ops": ops,
    }


def _every_op() -> list[dict]:
    return [_op(kind) for kind in REGISTRY]


def _pulls_the_outside_in() -> list[dict]:
    """Tines along both axes that bring what lies beyond the input's edges into
    view, then a vortex that stirs it."""
    w, h = CANVAS
    s = min(w, h)
    return [
        {"type": "tine", "point": [0, h / 2], "angle": 0, "alpha": 0.4 * w, "lambda": 0.15 * s},
        {"type": "tine", "point": [w / 2, 0], "angle": 90, "alpha": -0.4 * h, "lambda": 0.15 * s},
        _op("vortex"),
    ]


def _long_recipe(n: int) -> list[dict]:
    """``n`` gentle ops cycling through every op type, spread over the canvas: each
    example moved by a few percent of the canvas, its shifts and amplitudes at a
    fifth, ink at half its radius."""
    w, h = CANVAS
    kinds = list(REGISTRY)
    ops = []
    for i in range(n):
        definition = REGISTRY[kinds[i % len(kinds)]]
        op = _op(definition.type)
        shift = ((i * 7) % 11 - 5) * 0.04
        for param in definition.params:
            if param.kind == "point":
                op[param.name] = [op[param.name][0] + shift * w, op[param.name][1] - shift * h]
            elif param.slider in ("shift", "amplitude"):
                op[param.name] *= 0.2
        if definition.ink:
            op["radius"] *= 0.5
        ops.append(op)
    return ops


@dataclass(frozen=True)
class Case:
    """One render of the check: ``route`` is ``rgba`` (:meth:`Renderer.render`),
    ``planes`` (:meth:`Renderer.render_i420` with one matrix in and out) or
    ``converted`` (render_i420 between two matrices); ``blank``: no input."""

    name: str
    group: str
    recipe: dict
    blank: bool = False
    route: str = "rgba"


def cases() -> list[Case]:
    """The fixed set, first frames only (each case over an input is also rendered
    a second time by :func:`~marblevideo.opencl.selfcheck.check_device`, as group ``reused``)."""
    found = [Case(f"ops/{kind}", "ops", _recipe([_op(kind)])) for kind in REGISTRY]
    found += [Case(f"antialias/{aa}", "antialias", _recipe(_every_op(), aa)) for aa in PATTERNS]
    found += [
        Case(f"edges/{mode}", "edges", _recipe(_pulls_the_outside_in(), "rgss", mode))
        for mode in EDGE_MODES
    ]
    found += [Case(f"blank/{aa}", "blank", _recipe(_every_op(), aa), blank=True) for aa in PATTERNS]
    long_ops = _long_recipe(UNROLL_LIMIT + 5)
    found += [
        Case("long/input", "long", _recipe(long_ops, "rgss", "mirror")),
        Case("long/blank", "long", _recipe(long_ops, "quincunx"), blank=True),
    ]
    found += [
        Case("i420/planes", "i420", _recipe(_every_op(), "rgss", "mirror"), route="planes"),
        Case(
            "i420/converted",
            "i420",
            _recipe(_every_op(), "rgss", "background"),
            route="converted",
        ),
    ]
    return found
