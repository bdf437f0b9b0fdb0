"""The CLI branch for SVG and PDF output, ``--tolerance`` and ``--uv``
(kept apart from :mod:`marblevideo.cli` so that module stays small)."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from marblevideo.errors import UsageError
from marblevideo.limits import DEFAULT_TOLERANCE
from marblevideo.media.formats import VECTOR_EXTENSIONS, is_image_path

if TYPE_CHECKING:
    from marblevideo.recipe import Recipe


def render_extra(
    args: argparse.Namespace, recipe: Recipe, size: tuple[int, int] | None, out_ext: str
) -> int:
    from marblevideo.api import render_svg, render_uv_pass
    from marblevideo.cli.arguments import parse_view

    view = parse_view(args.view) if args.view else None
    if args.tolerance is not None and out_ext not in VECTOR_EXTENSIONS:
        raise UsageError("--tolerance: applies to .svg and .pdf outputs only")
    if out_ext in VECTOR_EXTENSIONS:
        if args.input is not None:
            raise UsageError(
                f"{args.output}: a recipe rendered over an input cannot be vectorized; "
                "SVG and PDF output take a blank-sheet recipe (no input)"
            )
        if args.uv or view:
            raise UsageError(f"{args.output}: --uv and --view do not apply to SVG or PDF output")
        stats = render_svg(
            recipe,
            args.output,
            time=args.time,
            size=size,
            tolerance=DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance,
            overwrite=args.overwrite,
        )
        if not args.quiet:
            print(f"wrote {args.output}: {stats.summary()}", file=sys.stderr)
        return 0
    # --uv: a still seen through a UV pass
    if not is_image_path(args.output):
        raise UsageError(f"{args.output}: --uv makes stills; give an image output")
    if args.input is not None and not is_image_path(args.input):
        raise UsageError(f"{args.input}: stills take an image input (.png .jpg .tif .webp)")
    if view or size:
        raise UsageError("--uv: the UV pass sets the output; drop --view and --size")
    render_uv_pass(
        args.input, recipe, args.uv, args.output, time=args.time, overwrite=args.overwrite
    )
    if not args.quiet:
        print(f"wrote {args.output}", file=sys.stderr)
    return 0
