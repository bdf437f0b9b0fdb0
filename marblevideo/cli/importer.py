"""``marblevideo import DESIGN -o RECIPE``: a pst-marble design (LaTeX, .pst or a
PostScript list of actions) written as a recipe (:mod:`marblevideo.pstmarble`)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from marblevideo.cli.arguments import Parser
from marblevideo.errors import UsageError
from marblevideo.media.output import atomic_output, check_output
from marblevideo.pstmarble import animate, import_design


def import_command(argv: list[str]) -> int:
    p = Parser(
        prog="marblevideo import",
        description="Write a pst-marble design (\\psMarble in a .tex or .pst file, or a "
        "PostScript list of actions) as a recipe. See docs/pst-marble.md.",
    )
    p.add_argument("design", help="the .tex, .pst or PostScript file")
    p.add_argument(
        "-o", "--output", required=True, help="the recipe to write (.json; - for standard output)"
    )
    p.add_argument("-y", "--overwrite", action="store_true", help="overwrite the output")
    p.add_argument(
        "--animate",
        type=float,
        metavar="S",
        help="give the ops start and end: one after another over S seconds (a video)",
    )
    args = p.parse_args(argv)
    if args.animate is not None and not args.animate > 0:
        raise UsageError(f"--animate: must be > 0 seconds, got {args.animate:g}")
    if args.output != "-":  # before the import: nothing is done for an output refused
        check_output(args.output, args.overwrite, [args.design])
        if Path(args.output).suffix.lower() != ".json":
            raise UsageError(f"{args.output}: a recipe is written as .json; give a .json name")
    doc = import_design(args.design, lambda line: print(f"marblevideo: {line}", file=sys.stderr))
    if args.animate is not None:
        doc = animate(doc, args.animate)
    text = json.dumps(doc, indent=2) + "\n"
    if args.output == "-":
        sys.stdout.write(text)
        return 0
    with atomic_output(args.output, args.overwrite, [args.design]) as tmp:
        tmp.write_text(text, encoding="utf-8")
    ops = len(doc["ops"])
    print(f"wrote {args.output}: {ops} ops on a {doc['canvas'][0]:g} x {doc['canvas'][1]:g} canvas")
    return 0
