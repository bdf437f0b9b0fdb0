"""A recipe stage by stage: ``python -m marblevideo.gallery -o steps.png``.

Renders the bundled samples/figure6.json (or ``--ops``) as a grid of labelled
pictures, one per stage, each showing the design just after that stage (its
ops and every earlier one complete, no later op begun). For Figure 6 these
are the paper's (a)-(j): the drops in three stages, the six combings, the
wave. The process as a video: ``marblevideo --ops samples/figure6.json -o process.mp4``.

The stages come from the recipe. Each op has a window: from its earliest
time (``start`` or a key time) to its latest (``end``, ``start`` or a key
time); an op with neither begins and ends when every op before it has
ended. The drops of one layout (``rings``, ``grid-drops``...) are one stage. Walking
the other ops in order, an op opens a new stage when

1. it starts no earlier than every earlier op ends (a pause, or one op
   following another end to start), or
2. it is an ink op (drop, spray) after a deforming op, or the other way round, or
3. it is an ink op on a centre its stage has already inked, and the ink op
   just before it was elsewhere: a round of drops ends when the dropper
   comes back to a spot (drops poured on one spot, a ring, stay one stage).

A stage is pictured at the time its last op ends (at least the time of the
stage before), with the ops of later stages left out.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from marblevideo.errors import MediaError, UsageError
from marblevideo.ops import is_ink
from marblevideo.recipe import Recipe

PROG = "python -m marblevideo.gallery"


@dataclass(frozen=True)
class Stage:
    """Ops ``first``..``last`` (indices into ``ops``) form stage ``label``,
    pictured at ``time``; ``title`` names its ops (``"14 drops"``, ``"comb"``)."""

    label: str
    first: int
    last: int
    time: float
    title: str


def _letter(n: int) -> str:
    """0 -> a, 25 -> z, 26 -> aa ..."""
    text = ""
    n += 1
    while n:
        n, r = divmod(n - 1, 26)
        text = chr(ord("a") + r) + text
    return text


def _title(ops) -> str:
    counts = Counter(op.layout[0] if op.layout else op.type for op in ops)
    if len(counts) == 1 and ops[0].layout:
        return ops[0].layout[0]
    return ", ".join(k if n == 1 else f"{n} {k}s" for k, n in counts.items())


def stages(recipe: Recipe) -> list[Stage]:
    """The recipe's stages by the rule in this module's docstring."""
    groups: list[list] = []
    done = 0.0  # when every op so far has ended
    inked: set = set()
    previous = previous_center = None
    for op in recipe.ops:
        if op.times:
            begin, finish = min(op.times), max(op.times)
        else:
            begin = finish = done
        ink = is_ink(op.type)
        center = tuple(op.params["center"].at(begin)) if ink else None
        same_layout = (
            op.layout is not None and previous is not None and op.layout == previous.layout
        )
        new = not same_layout and (
            not groups
            or begin >= done
            or ink != is_ink(previous.type)
            or (ink and center in inked and center != previous_center)
        )
        if new:
            groups.append([])
            inked = set()
        groups[-1].append(op)
        if ink:
            inked.add(center)
        previous, previous_center = op, center
        done = max(done, finish)
    out, time = [], 0.0
    for n, group in enumerate(groups):
        time = max([time, *(max(op.times) for op in group if op.times)])
        label = _letter(n)
        out.append(Stage(label, group[0].index, group[-1].index, time, _title(group)))
    return out


def upto(recipe: Recipe, stage: Stage) -> Recipe:
    """The recipe with the ops after ``stage`` left out (they never begin)."""
    ops = tuple(
        op if op.index <= stage.last else dataclasses.replace(op, start=math.inf, end=None)
        for op in recipe.ops
    )
    return dataclasses.replace(recipe, ops=ops)


def strip(recipe: Recipe, size: int = 192, columns: int = 5, marbler=None) -> np.ndarray:
    """The stages as one RGB image: ``columns`` per row, a label under each."""
    import cv2

    from marblevideo.marbler import Marbler

    marbler = marbler or Marbler(recipe)
    pad, label_h = 6, 22
    found = stages(recipe)
    columns = max(1, min(columns, len(found)))
    rows = max(1, -(-len(found) // columns))
    cell_w, cell_h = size + pad, size + label_h + pad
    sheet = np.full((rows * cell_h + pad, columns * cell_w + pad, 3), 255, np.uint8)
    for n, stage in enumerate(found):
        staged = Marbler(upto(recipe, stage), renderer=marbler.renderer)
        img = staged.render(None, stage.time, (size, size))[..., :3]
        y, x = pad + (n // columns) * cell_h, pad + (n % columns) * cell_w
        sheet[y : y + size, x : x + size] = img
        cv2.putText(
            sheet,
            f"({stage.label}) {stage.title}",
            (x + 4, y + size + 16),
            cv2.FONT_HERSHEY_SIMPLEX,
            0.45,
            (40, 40, 40),
            1,
            cv2.LINE_AA,
        )
    return sheet


def main(argv: list[str] | None = None) -> int:
    """The command line; one-line errors, exit status 2 for a user's mistake."""
    from marblevideo.cli.arguments import reported

    return reported(PROG, lambda: _main(argv))


def _main(argv: list[str] | None) -> int:
    from marblevideo.bundled import samples_path
    from marblevideo.cli.arguments import Parser
    from marblevideo.marbler import as_recipe, blank_canvas
    from marblevideo.media.formats import is_image_path
    from marblevideo.media.images import write_image
    from marblevideo.media.output import atomic_output, check_output

    p = Parser(
        prog=PROG,
        description=__doc__.split("\n\n")[0],
        epilog="The stages come from the ops' start/end windows; see the module docstring.",
    )
    p.add_argument("--ops", metavar="RECIPE", help="blank-sheet recipe (samples/figure6.json)")
    p.add_argument("-o", "--output", required=True, help="image file (.png .jpg .tif .webp)")
    p.add_argument("--size", type=int, default=192, help="side of each stage picture (192)")
    p.add_argument("--columns", type=int, default=5, help="pictures per row (5)")
    p.add_argument("-y", "--overwrite", action="store_true", help="replace an existing output")
    args = p.parse_args(argv)
    if not 1 <= args.size <= 4096:
        raise UsageError(f"--size: must be 1..4096 pixels, got {args.size}")
    if args.columns < 1:
        raise UsageError(f"--columns: must be >= 1, got {args.columns}")
    if not is_image_path(args.output):
        raise UsageError(f"{args.output}: give an image output (.png .jpg .tif .webp)")
    check_output(Path(args.output), args.overwrite)
    if args.ops is None:
        try:
            args.ops = samples_path("figure6.json")
        except FileNotFoundError as exc:  # an installation without its samples
            raise MediaError(str(exc)) from None
    recipe = as_recipe(args.ops)
    blank_canvas(recipe)
    if not recipe.ops:
        raise UsageError(f"{recipe.source}: the recipe has no ops, so no stages to show")
    sheet = strip(recipe, args.size, args.columns)
    rgba = np.concatenate([sheet, np.full(sheet.shape[:2] + (1,), 255, np.uint8)], axis=2)
    with atomic_output(args.output, args.overwrite) as tmp:
        write_image(tmp, rgba, alpha=False, fmt=Path(args.output).suffix, name=args.output)
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
