"""``marblevideo export RECIPE -o OUT``: a recipe written as a program another
host runs (:mod:`marblevideo.export`; docs/export.md)."""

from __future__ import annotations

import sys

from marblevideo.cli.arguments import Parser
from marblevideo.limits import DEFAULT_FPS, EXPORT_CONSTANT_BYTES

EPILOG = """\
examples:
  marblevideo export samples/swirl.json -o swirl.cl --fps 25
  ffmpeg -init_hw_device opencl=ocl -filter_hw_device ocl -i samples/coffee.mp4 \\
    -vf "format=rgba,hwupload,program_opencl=source=swirl.cl:kernel=marble,\\
hwdownload,format=rgba,format=yuv420p" -c:a copy out.mp4

The .cl file's first comment gives the exact ffmpeg commands (the filter and the
blank-sheet source). See docs/export.md.
"""


def export_command(argv: list[str]) -> int:
    import argparse

    p = Parser(
        prog="marblevideo export",
        description="Write a recipe as a program for another host: .cl, an OpenCL "
        "program for ffmpeg's program_opencl filter and openclsrc source.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recipe", help="the recipe (a file, or a preset's name)")
    p.add_argument(
        "-o", "--output", required=True, help="the file to write (.cl; - for standard output)"
    )
    p.add_argument("--to", choices=["ffmpeg"], help="the format (default: by the extension)")
    p.add_argument(
        "--fps",
        type=float,
        default=DEFAULT_FPS,
        help=f"frames per second of the video it will run over (.cl: frame index i is the "
        f"recipe at i / fps; default {DEFAULT_FPS:g})",
    )
    p.add_argument(
        "--constant-memory",
        type=int,
        metavar="BYTES",
        help=f".cl: the constant memory the frames' data may take (default "
        f"{EXPORT_CONSTANT_BYTES}, what every OpenCL device gives; more for a device that "
        "reports more: clinfo's max constant buffer size)",
    )
    p.add_argument("-y", "--overwrite", action="store_true", help="overwrite the output")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary on stderr")
    args = p.parse_args(argv)

    from marblevideo.export import export_source, format_of
    from marblevideo.media.output import atomic_output, check_output
    from marblevideo.recipe.load import load_recipe

    check_output(args.output, args.overwrite, [args.recipe])
    fmt = format_of(args.output, args.to)
    recipe = load_recipe(args.recipe)
    source = export_source(recipe, fmt, args.fps, args.constant_memory)
    if args.output == "-":
        sys.stdout.write(source)
        return 0
    with atomic_output(args.output, args.overwrite, [args.recipe]) as tmp:
        tmp.write_text(source, encoding="utf-8")
    if not args.quiet:
        print(
            f"marblevideo: wrote {args.output}: {len(recipe.ops)} ops for ffmpeg "
            f"(program_opencl kernel marble, openclsrc kernel marble_sheet) at {args.fps:g} fps",
            file=sys.stderr,
        )
    return 0
