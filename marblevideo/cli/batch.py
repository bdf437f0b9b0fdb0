"""``marblevideo batch PATTERN... --ops RECIPE -o TEMPLATE``: many inputs through
one recipe (:mod:`marblevideo.scale.batch`)."""

from __future__ import annotations

import argparse
import sys

from marblevideo.cli.arguments import Parser, add_log_arguments, configure_logging, parse_size
from marblevideo.errors import MediaError
from marblevideo.recipe.frame import FIT_MODES

EPILOG = """\
examples:
  marblevideo batch 'photos/*.jpg' --ops comb-wave -o 'out/{stem}.png'
  marblevideo batch 'clips/*.mp4' --ops swirl -o 'out/{stem}-marbled.mp4' --jobs 2
  marblevideo batch 'in/*.jpg' --ops swirl -o 'out/{stem}.png' --cluster ray

output fields: {stem} {name} {suffix} {parent} {index} (e.g. {index:04d})
A re-run resumes: items the manifest records as done with the same recipe and
options are skipped while their output exists; other existing outputs need -y.
--cluster ray: each item on a Ray cluster's workers ($RAY_ADDRESS, else a
local Ray); the machines must see the inputs and outputs at the same paths.
exit status: 0 all done, 1 an item failed (the others are written), 2 usage error
"""


def build_parser() -> Parser:
    p = Parser(
        prog="marblevideo batch",
        description="Render many inputs through one recipe, each to an output named "
        "from a template; serially, on a local process pool, or on a Ray cluster.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("inputs", nargs="+", metavar="PATTERN", help="input files or glob patterns")
    p.add_argument("--ops", required=True, metavar="RECIPE", help="recipe JSON file or preset")
    p.add_argument("-o", "--output", required=True, metavar="TEMPLATE", help="output name template")
    p.add_argument("-y", "--overwrite", action="store_true", help="replace existing outputs")
    p.add_argument("--jobs", type=int, help="worker processes (default 1); with --cluster "
                   "ray, Ray workers (default: one per GPU, else per CPU)")  # fmt: skip
    p.add_argument("--cluster", choices=("ray",), help="run the items on a Ray cluster "
                   "($RAY_ADDRESS, else a local Ray); pip install 'marblevideo[ray]'")  # fmt: skip
    p.add_argument("--manifest", metavar="FILE", help="the batch's record (default: "
                   "marblevideo-batch.json beside the first output)")  # fmt: skip
    p.add_argument("--size", metavar="WxH", help="output size (default: each input's)")
    p.add_argument("--fit", choices=FIT_MODES, help="an input of another aspect than --size")
    p.add_argument("--time", type=float, metavar="T", help="still outputs: render at T seconds")
    p.add_argument("--device", help="OpenCL device: P:D, a name, see `marblevideo devices`")
    p.add_argument("--progress", choices=("auto", "bar", "json", "off"), default="auto",
                   help="progress of the whole batch on stderr")  # fmt: skip
    add_log_arguments(p)
    return p


def batch_command(argv: list[str]) -> int:
    from marblevideo.scale.batch import run_batch

    args = build_parser().parse_args(argv)
    configure_logging(args.verbose)
    options = {"device": args.device}
    if args.size:
        options["size"] = parse_size(args.size)
    if args.fit:
        options["fit"] = args.fit
    if args.time is not None:
        options["time"] = args.time

    def notify(line: str) -> None:
        if not args.quiet:
            print(f"marblevideo: {line}", file=sys.stderr)

    result = run_batch(
        args.inputs,
        args.ops,
        args.output,
        overwrite=args.overwrite,
        jobs=args.jobs,
        cluster=args.cluster,
        manifest=args.manifest,
        progress="off" if args.quiet else args.progress,
        notify=notify,
        **options,
    )
    if result.failed:
        dst, error = next(iter(result.failed.items()))
        more = f" (and {len(result.failed) - 1} more)" if len(result.failed) > 1 else ""
        raise MediaError(f"batch: {result.summary()}; first: {error}{more}")
    notify(f"batch: {result.summary()}")
    return 0
