"""``marblevideo export RECIPE -o OUT``: a recipe written as a program another
host runs (:mod:`marblevideo.export`; docs/export.md)."""

from __future__ import annotations

import sys
from pathlib import Path

from marblevideo.cli.arguments import Parser
from marblevideo.errors import UsageError
from marblevideo.limits import DEFAULT_FPS, EXPORT_CONSTANT_BYTES

EPILOG = """\
examples:
  marblevideo export samples/swirl.json -o swirl.cl --fps 25
  marblevideo export nonpareil -o nonpareil.frag --sheet   # GStreamer glshader (+ .vert)
  marblevideo export samples/swirl.json -o swirl.fs          # ISF: VDMX, MadMapper, Resolume
  ffmpeg -init_hw_device opencl=ocl -filter_hw_device ocl -i samples/coffee.mp4 \\
    -vf "format=rgba,hwupload,program_opencl=source=swirl.cl:kernel=marble,\\
hwdownload,format=rgba,format=yuv420p" -c:a copy out.mp4

The .cl file's first comment gives the exact ffmpeg commands (the filter and the
blank-sheet source). See docs/export.md for every host.
"""


#: What each format's file is, for the summary line.
SUMMARIES = {
    "ffmpeg": "for ffmpeg (program_opencl kernel marble, openclsrc kernel marble_sheet)",
    "gstreamer": "{kind} for GStreamer's glshader (GLSL 3.30; GST_GL_API=opengl3)",
    "isf": "{kind} in ISF 2.0",
    "shadertoy": "{kind} for Shadertoy's Image tab",
}


def _parser():
    import argparse

    p = Parser(
        prog="marblevideo export",
        description="Write a recipe as a program for another host: .cl, an OpenCL "
        "program for ffmpeg's program_opencl filter and openclsrc source; .frag, a GLSL "
        "shader for GStreamer's glshader (its vertex shader beside, as .vert); .fs, an "
        "ISF 2.0 shader (VDMX, MadMapper, Millumin, Resolume's Wire, TouchDesigner).",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recipe", help="the recipe (a file, or a preset's name)")
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="the file to write (.cl, .frag, .fs; - for standard output, with --to)",
    )
    p.add_argument(
        "--to",
        choices=["ffmpeg", "gstreamer", "isf", "shadertoy"],
        help="the format (default: by the extension; shadertoy only by --to)",
    )
    p.add_argument(
        "--sheet",
        action="store_true",
        help=".frag, .fs, shadertoy: a generator on a blank sheet (default: a filter of the input)",
    )
    p.add_argument(
        "--fps",
        type=float,
        default=DEFAULT_FPS,
        help=f".cl: the frame rate of the video it will run over (frame index i is the recipe "
        f"at i / fps); .frag, .fs: the steps the recipe's motion is sampled in (the host's "
        f"time t shows the frame nearest t * fps); default {DEFAULT_FPS:g}",
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
    return p


def export_command(argv: list[str]) -> int:
    args = _parser().parse_args(argv)

    from marblevideo.export import export_source, format_of
    from marblevideo.export.shader import GSTREAMER_VERTEX
    from marblevideo.media.output import atomic_output, check_output
    from marblevideo.recipe.load import load_recipe

    check_output(args.output, args.overwrite, [args.recipe])
    fmt = format_of(args.output, args.to)
    if args.sheet and fmt == "ffmpeg":
        raise UsageError("--sheet: a .cl file has both kernels (marble_sheet is the sheet)")
    files = {args.output: None}
    if fmt == "gstreamer" and args.output != "-":
        files[str(Path(args.output).with_suffix(".vert"))] = GSTREAMER_VERTEX
    for path in files:
        check_output(path, args.overwrite, [args.recipe])
    recipe = load_recipe(args.recipe)
    files[args.output] = export_source(
        recipe, fmt, args.fps, args.constant_memory, sheet=args.sheet
    )
    if args.output == "-":
        sys.stdout.write(files[args.output])
        return 0
    for path, text in files.items():
        with atomic_output(path, args.overwrite, [args.recipe]) as tmp:
            tmp.write_text(text, encoding="utf-8")
    if not args.quiet:
        what = SUMMARIES[fmt].format(kind="a generator" if args.sheet else "a filter")
        names = " and ".join(files)
        print(f"marblevideo: wrote {names}: {len(recipe.ops)} ops, {what}", file=sys.stderr)
    return 0
