"""The paper's Figure 6, step by step: ``python -m marblevideo.gallery -o strip.png``.

Renders samples/figure6.json (or ``--ops``) just after each stage of the
paper's procedure finishes, (a)-(j): the drop pattern in three stages, the
six combings, the wave, as a grid of labelled images (two rows of five).
Stage times are the ends of op groups: a stage is complete when its last op
has reached progress 1. The process as a video:
``marblevideo --ops samples/figure6.json -o process.mp4``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

#: (label, which op ends the stage) for samples/figure6.json: 25 drops (ops 0-24,
#: five rings), six combs (25-30), a wave (31).
FIGURE6_STAGES = (
    ("a", 4),
    ("b", 14),
    ("c", 24),
    ("d", 25),
    ("e", 26),
    ("f", 27),
    ("g", 28),
    ("h", 29),
    ("i", 30),
    ("j", 31),
)


def stage_times(recipe, stages=FIGURE6_STAGES) -> list[tuple[str, float]]:
    """(label, time) just after op ``k`` of each stage ends (its ``end``, else ``start``)."""
    out = []
    for label, k in stages:
        op = recipe.ops[k]
        t = op.end if op.end is not None else (op.start or 0.0)
        out.append((label, t + 1e-6))
    return out


def strip(recipe, size: int = 192, columns: int = 5, marbler=None) -> np.ndarray:
    """The stages as one RGB image: ``columns`` per row, a label under each."""
    import cv2

    from marblevideo.api import Marbler

    marbler = marbler or Marbler(recipe)
    pad, label_h = 6, 22
    times = stage_times(marbler.recipe)
    rows = -(-len(times) // columns)
    cell_w, cell_h = size + pad, size + label_h + pad
    sheet = np.full((rows * cell_h + pad, columns * cell_w + pad, 3), 255, np.uint8)
    for n, (label, t) in enumerate(times):
        img = marbler.render(None, t, (size, size))[..., :3]
        y, x = pad + (n // columns) * cell_h, pad + (n % columns) * cell_w
        sheet[y : y + size, x : x + size] = img
        text = f"({label}) t={t:.2f}s"
        cv2.putText(
            sheet,
            text,
            (x + 4, y + size + 16),
            cv2.FONT_HERSHEY_SIMPLEX,
            0.45,
            (40, 40, 40),
            1,
            cv2.LINE_AA,
        )
    return sheet


def main(argv: list[str] | None = None) -> int:
    from marblevideo.api import as_recipe
    from marblevideo.images import write_image
    from marblevideo.output import atomic_output

    p = argparse.ArgumentParser(prog="python -m marblevideo.gallery", description=__doc__)
    p.add_argument("--ops", default=str(ROOT / "samples" / "figure6.json"))
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--size", type=int, default=192, help="side of each stage image (192)")
    p.add_argument("-y", "--overwrite", action="store_true")
    args = p.parse_args(argv)
    recipe = as_recipe(args.ops)
    sheet = strip(recipe, args.size)
    rgba = np.concatenate([sheet, np.full(sheet.shape[:2] + (1,), 255, np.uint8)], axis=2)
    with atomic_output(args.output, args.overwrite) as tmp:
        write_image(tmp, rgba, alpha=False, fmt=Path(args.output).suffix)
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
