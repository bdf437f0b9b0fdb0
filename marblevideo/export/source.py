"""What every exported source shares: float literals that read back to the same
float32, and the defines of the one-pixel-per-invocation program (LANES, CHAINS
and ROWS 1, the pattern's size, the canvas, the background's rows) with the
walk's op types."""

from __future__ import annotations

import numpy as np

from marblevideo.opencl.program import UNROLL_LIMIT


def literal(value: float) -> str:
    """A float32 as a C (and GLSL) float literal that reads back to the same float32."""
    value = np.float32(value)
    if not np.isfinite(value):
        raise ValueError(f"cannot write {value} as a literal")
    text = str(value)
    if not any(c in text for c in ".e"):
        text += ".0"
    return text + "f"


def walk_types(recipe) -> tuple[str, ...] | None:
    """The op types the walk unrolls, or None for the loop walk (long recipes)."""
    types = tuple(op.type for op in recipe.ops)
    return types if len(types) <= UNROLL_LIMIT else None


def one_pixel_defines(recipe, table) -> list[str]:
    """The defines both kinds of export start with (see the module)."""
    cw, ch = recipe.canvas or (0.0, 0.0)
    return [
        "#define LANES 1",
        "#define CHAINS 1",
        "#define ROWS 1",
        f"#define NSAMPLES {len(table.samples)}",
        f"#define MV_BACKGROUND_FIRST {table.background_first}",
        f"#define MV_BACKGROUND_COUNT {len(table.background)}",
        f"#define MV_CANVAS_W {literal(cw)}",
        f"#define MV_CANVAS_H {literal(ch)}",
    ]
