"""``marblevideo [INPUT] --ops RECIPE -o OUTPUT``: render a still, a video, an SVG.

What is rendered follows from the files (:mod:`.applies`): an image output is
a still (of an image, a blank sheet, or a video's frame); a video output is a
video (of a video, a still animated, or a blank sheet); an .svg or .pdf
output, ``--uv`` or ``--tolerance`` go to :mod:`.vectors`.
"""

from __future__ import annotations

import argparse
import functools
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from marblevideo.cli.applies import check_options
from marblevideo.cli.arguments import (
    Parser,
    add_encoder_arguments,
    add_log_arguments,
    configure_logging,
    parse_encoder_opts,
    parse_view,
)
from marblevideo.cli.realtime import render_realtime, wants_realtime
from marblevideo.cli.sizes import resolve_size
from marblevideo.cli.vectors import render_extra
from marblevideo.errors import UsageError
from marblevideo.limits import DEFAULT_FPS, DEFAULT_TOLERANCE
from marblevideo.media.formats import is_stdio, output_kinds
from marblevideo.recipe.frame import FIT_MODES
from marblevideo.version import __version__

if TYPE_CHECKING:
    from marblevideo.media.video import VideoOptions

EPILOG = """\
examples:
  marblevideo in.mp4 --ops samples/swirl.json -o out.mp4
  marblevideo photo.jpg --ops samples/comb-wave.json -o out.png --time 2
  marblevideo --ops samples/figure6.json -o design.png --size 2048x2048
  marblevideo --ops bouquet -o bouquet.png    a preset (a bundled recipe) by name
  marblevideo presets            list the presets; presets NAME prints one's JSON
  marblevideo ops                list the op types and their parameters (ops TYPE: one)
  marblevideo devices            list OpenCL devices
  marblevideo devices --check    test each device against the NumPy reference
  marblevideo schema             print the recipe's JSON Schema
  marblevideo live test --ops samples/swirl.json --preview   live (see live --help)
  marblevideo film.mp4 --ops swirl -o out.mp4 --cluster ray   in segments on Ray
  marblevideo design photo.jpg --ops mine.json   draw a recipe in the browser (design --help)

exit status: 0 done, 1 runtime failure, 2 usage or recipe error, 130/143 interrupted
"""


#: The parser's options, one table per group of ``--help``: (flags, add_argument keywords).
_MAIN = (
    (
        ("input",),
        dict(
            nargs="?",
            help="image, video, image sequence (name_%%04d.png), URL, or - (standard input); "
            "omit for a blank sheet",
        ),
    ),
    (("--ops",), dict(required=True, metavar="RECIPE", help="recipe JSON file")),
    (
        ("-o", "--output"),
        dict(
            required=True,
            help="output; the format follows the extension: "
            f"{output_kinds().replace('%', '%%')}; or - (standard output, with --format)",
        ),
    ),
    (("-y", "--overwrite"), dict(action="store_true", help="replace an existing output")),
    (
        ("--size",),
        dict(
            metavar="WxH",
            help="output size (default: input or canvas); W or xH: the other side keeps "
            "the input's aspect, even (as ffmpeg's scale=W:-2)",
        ),
    ),
    (
        ("--fit",),
        dict(
            choices=FIT_MODES,
            help="an input of another aspect than --size: stretch it (default), crop it to "
            "fill, or pad it with the recipe's background; a blank sheet's canvas: fitted and "
            "centred (default, as pad), cropped to fill, or stretched",
        ),
    ),
    (
        ("--format",),
        dict(
            metavar="NAME",
            help="output format by name, for -o - (matroska, nut, mpegts, y4m, mp4, gif, ...; "
            "png, jpeg, tiff for a still) or to force one (webp: an animated WebP)",
        ),
    ),
    (
        ("--time",),
        dict(
            type=float,
            metavar="T",
            help="stills: render at T seconds (default: the end of the animation; "
            "from a video, its frame at T, default the first)",
        ),
    ),
)
_VECTORS = (
    (
        ("--view",),
        dict(
            metavar="X,Y,W,H",
            help="stills: render this canvas window (deep zoom; exact at any size)",
        ),
    ),
    (
        ("--tolerance",),
        dict(
            type=float,
            metavar="PX",
            help="SVG/PDF output: outline tolerance in output pixels "
            f"(default {DEFAULT_TOLERANCE})",
        ),
    ),
    (
        ("--uv",),
        dict(
            metavar="PASS",
            help="render the design through a UV pass (.png 16-bit / .exr; R = u, G = v)",
        ),
    ),
)
_VIDEO = (
    (("--start",), dict(type=float, metavar="S", help="render from S seconds of the input")),
    (("--end",), dict(type=float, metavar="S", help="render up to S seconds of the input")),
    (
        ("--duration",),
        dict(
            type=float,
            metavar="S",
            help="length: of a blank sheet or a still animated (default: the animation plus "
            "1 s); of a video input, from --start",
        ),
    ),
    (
        ("--fps",),
        dict(
            type=float,
            help=f"frame rate: of a blank sheet or a still animated ({DEFAULT_FPS:g}); "
            f"converts a video's (as ffmpeg's fps filter); the rate an image sequence is "
            f"read at ({DEFAULT_FPS:g})",
        ),
    ),
    (
        ("--audio",),
        dict(
            choices=("auto", "copy", "aac", "none"),
            help="auto (default): copy audio bit-exact, but re-encode to AAC the Opus, FLAC, "
            "Vorbis or PCM that an MP4 or MOV would not play everywhere; copy: always where "
            "the container holds it; aac: re-encode; none: drop it",
        ),
    ),
    (
        ("--soundtrack",),
        dict(
            metavar="FILE",
            help="a sound file: the output's audio (its first sample at t = 0, in place of "
            "the input's) and what audio signals (audio.level, audio.low, ...) follow",
        ),
    ),
    (
        ("--exact-walk",),
        dict(
            action="store_true",
            help="animated frames over an input: walk every subsample (default: interpolate "
            'the map from a walked lattice where it is smooth; the recipe\'s "lattice": '
            "false too)",
        ),
    ),
    (
        ("--automation",),
        dict(
            metavar="FILE",
            help="write the take: the recipe with its motion strokes as ordinary strokes "
            "and no motion (rendering FILE over the same input gives the same frames)",
        ),
    ),
    (
        ("--realtime",),
        dict(
            action="store_true",
            help="play the render at the input's own pace to a stream (-o rtmp://HOST/APP/KEY; "
            "a stream output implies it), as a live session of the file",
        ),
    ),
)
#: After the encoder's flags (:func:`.arguments.add_encoder_arguments`) in the video group.
_PROGRESS = (
    (
        ("--progress",),
        dict(
            choices=("auto", "bar", "json", "off"),
            default="auto",
            help="progress on stderr: a bar on terminals (auto), JSON lines, or off",
        ),
    ),
)
_SCALE_OUT = (
    (
        ("--cluster",),
        dict(
            choices=("ray",),
            help="render a video in segments on a Ray cluster ($RAY_ADDRESS, else a local "
            "Ray), joined into the output; the machines must see input and output at the "
            "same paths",
        ),
    ),
    (
        ("--segments",),
        dict(
            type=int,
            metavar="N",
            help="cut the input into N segments at its keyframes (default: one per about 45 s)",
        ),
    ),
    (
        ("--jobs",),
        dict(type=int, metavar="N", help="Ray workers (default: one per GPU, else per CPU)"),
    ),
)


def _add(group, table) -> None:
    for flags, options in table:
        group.add_argument(*flags, **options)


def _render_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="marblevideo",
        description="Marble videos, live sources and stills with the closed-form "
        "operations of Mathematical Marbling (Lu et al. 2012), rendered by OpenCL.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _add(p, _MAIN)
    _add(p.add_argument_group("vectors, zoom, textures"), _VECTORS)
    p.add_argument("--device", help="OpenCL device: P:D, a name, see `marblevideo devices`")
    add_log_arguments(p)
    p.add_argument("--version", action="version", version=f"marblevideo {__version__}")
    video = p.add_argument_group("video")
    _add(video, _VIDEO)
    add_encoder_arguments(video, preset_default="medium")
    _add(p.add_argument_group("scale-out (pip install 'marblevideo[ray]')"), _SCALE_OUT)
    _add(video, _PROGRESS)
    return p


def _notify(message: str) -> None:
    print(f"marblevideo: {message}", file=sys.stderr)


def _where(dst) -> str:
    return "standard output" if is_stdio(dst) else str(dst)


def render_command(argv: list[str]) -> int:
    args = _render_parser().parse_args(argv)  # --help and --version import nothing heavy
    if wants_realtime(args):
        return render_realtime(args)
    from marblevideo.api import render_still
    from marblevideo.recipe.load import read_recipe
    from marblevideo.signals.follow import check as check_signals
    from marblevideo.signals.follow import follow

    configure_logging(args.verbose)
    document, recipe = read_recipe(args.ops)  # validated before any input is opened
    size = resolve_size(args.size, args.input)
    job, _ = check_options(args)
    check_signals(recipe, args.input, args.soundtrack)  # refusals before any work
    if job in ("vectors", "uv") or args.tolerance is not None:
        recipe = follow(recipe, args.input, args.soundtrack)
        return render_extra(args, recipe, size, Path(args.output).suffix.lower())
    if job == "still":
        dst = render_still(
            args.input,
            recipe,
            args.output,
            time=args.time,
            size=size,
            view=parse_view(args.view) if args.view else None,
            fit=args.fit,
            format=args.format,
            rate=args.fps,
            overwrite=args.overwrite,
            device=args.device,
            progress="off" if args.quiet else args.progress,
            notify=None if args.quiet else _notify,
            soundtrack=args.soundtrack,
        )
        if not args.quiet:
            print(f"wrote {_where(dst)}", file=sys.stderr)
        return 0
    if args.view:
        raise UsageError(f"{args.output}: --view makes stills; give an image output")
    if args.cluster:
        from marblevideo.scale.segmented import render_split

        render = functools.partial(
            render_split, cluster=args.cluster, segments=args.segments, jobs=args.jobs
        )
    else:
        from marblevideo.api import render_video

        render = render_video
    take = dict(automation=args.automation, document=document)
    options = _video_options(args, size)
    stats = render(args.input, recipe, args.output, device=args.device, options=options, **take)
    if not args.quiet:
        print(f"marblevideo: {stats.summary(_where(args.output))}", file=sys.stderr)
    return 0


def _video_options(args: argparse.Namespace, size: tuple[int, int] | None) -> VideoOptions:
    """The job's options of the flags, checked by the job against its input."""
    from marblevideo.media.video import VideoOptions

    return VideoOptions(
        codec=args.codec,
        crf=args.crf,
        preset=args.preset,
        pix_fmt=args.pix_fmt,
        encoder_opts=parse_encoder_opts(args.encoder_opt),
        audio=args.audio or "auto",
        start=args.start,
        end=args.end,
        size=size,
        fit=args.fit,
        format=args.format,
        overwrite=args.overwrite,
        soundtrack=args.soundtrack,
        quiet=args.quiet,
        progress=args.progress,
        verbose=args.verbose,
        exact_walk=args.exact_walk,
        fps=args.fps,
        duration=args.duration,
    )
