"""``marblevideo design [INPUT] --ops FILE``: the browser designer
(:mod:`marblevideo.design`), served on 127.0.0.1 until Ctrl-C (SIGINT),
SIGTERM or ``--duration``; each is a normal end (exit 0).
"""

from __future__ import annotations

import argparse
import contextlib
import signal
import sys
import threading
import webbrowser
from pathlib import Path

from marblevideo.cli.arguments import Parser, add_log_arguments, configure_logging, parse_size
from marblevideo.cli.controllers import (
    add_controller_arguments,
    check_controllers,
    close_all,
    start_controllers,
)
from marblevideo.errors import UsageError
from marblevideo.limits import DEFAULT_PORT


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="marblevideo design",
        description="Draw a marbling recipe by hand in the browser (drop ink, comb, rake, "
        "swirl...), over a blank sheet, a photo, a video or a live source; every change "
        "is saved to FILE.",
        epilog="examples:\n"
        "  marblevideo design --ops mine.json\n"
        "  marblevideo design samples/coffee.jpg --ops coffee-swirl.json\n"
        "  marblevideo design test --ops live.json --no-browser --port 8800\n\n"
        "The page's HTTP API (GET/PUT /api/recipe, GET /api/frame.png?t=T&w=W) is in the "
        "README.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "input",
        nargs="?",
        help="an image, a video or URL, a live source (test, a camera index, /dev/videoN); "
        "default: a blank sheet",
    )
    p.add_argument(
        "--ops",
        required=True,
        metavar="FILE",
        help="the recipe to edit (created if missing); a preset's name edits a copy of it, "
        "./NAME.json",
    )
    p.add_argument(
        "-y", "--overwrite", action="store_true", help="replace an existing copy of the preset"
    )
    p.add_argument(
        "--canvas",
        metavar="WxH",
        help="canvas of a new FILE (default: the input's size, or 1024x768 for a blank sheet)",
    )
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"port ({DEFAULT_PORT}; 0: any)")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds")
    p.add_argument("--size", metavar="WxH", help="size of the 'test' source, or asked of a camera")
    p.add_argument("--device", help="OpenCL device: P:D, a name, see `marblevideo devices`")
    add_controller_arguments(p, automation=False)
    add_log_arguments(p)
    return p


def _checked(args, preset) -> tuple[tuple[int, int] | None, tuple[int, int] | None]:
    """The options' faults as UsageError (exit 2), before anything opens: (canvas, size);
    ``preset``: the preset that ``args.ops`` will be a copy of, or None."""
    from marblevideo.design.backdrop import LIVE, check_spec

    if args.input is not None:
        check_spec(args.input)
    if not 0 <= args.port <= 65535:
        raise UsageError(f"--port: must be 0..65535, got {args.port}")
    if args.duration is not None and args.duration <= 0:
        raise UsageError(f"--duration: must be > 0, got {args.duration}")
    path = Path(args.ops)
    if path.is_dir():
        raise UsageError(f"{path}: is a folder; --ops names the recipe file to edit")
    if str(path.parent) and not path.parent.is_dir():
        raise UsageError(f"{path}: folder {path.parent} does not exist")
    try:
        canvas = parse_size(args.canvas) if args.canvas else None
    except UsageError as exc:
        raise UsageError(str(exc).replace("--size", "--canvas", 1)) from None
    if canvas is not None and (path.exists() or preset is not None):
        raise UsageError(
            f"--canvas: {path} exists and keeps its own canvas (edit it there, or name a new file)"
        )
    size = parse_size(args.size) if args.size else None
    live = bool(args.input and LIVE.match(args.input))
    if size is not None and not live:
        raise UsageError("--size: applies to a live source only (test, a camera)")
    for option, value in (("--osc", args.osc), ("--midi", args.midi)):
        if value is not None and not live:
            raise UsageError(f"{option}: controllers drive a live source only (test, a camera)")
    return canvas, size


def design_command(argv: list[str]) -> int:
    """The ``design`` command; returns the exit status (MarbleError propagates)."""
    from marblevideo.cli.working_copy import copy_preset, plan_working_copy
    from marblevideo.design.backdrop import open_backdrop
    from marblevideo.design.session import DesignSession
    from marblevideo.marbler import blank_canvas
    from marblevideo.recipe import load_recipe
    from marblevideo.serve.recipefile import DEFAULT_CANVAS, RecipeFile
    from marblevideo.serve.server import Server

    args = build_parser().parse_args(argv)
    configure_logging(args.verbose)
    args.ops, preset = plan_working_copy(args.ops, args.overwrite)
    canvas, size = _checked(args, preset)
    if preset is not None:  # checked before the copy is written
        check_controllers(args, load_recipe(preset))
        copy_preset(preset, args.ops, args.quiet)
    if canvas is None and args.input is None:
        canvas = DEFAULT_CANVAS
    # a bad FILE is refused here (exit 2); a bad save by another program later is said
    say = lambda m: print(f"marblevideo: {m}", file=sys.stderr, flush=True)  # noqa: E731
    # over a blank sheet, a save (or a change on disk) without a canvas is refused:
    # the sheet's size is the canvas
    check = blank_canvas if args.input is None else None
    document = RecipeFile(args.ops, canvas, notify=say, check=check)
    if preset is None:
        check_controllers(args, document.recipe)
    if args.input is None and document.recipe.canvas is None:
        raise UsageError(
            f"{args.ops}: canvas: a blank-sheet design needs canvas [W, H] (or give an INPUT)"
        )
    stop = threading.Event()
    with contextlib.ExitStack() as stack:  # undone in reverse order, whatever happens
        backdrop = open_backdrop(args.input, size)
        stack.callback(backdrop.close)
        session = DesignSession(document, backdrop, device=args.device)
        stack.callback(session.close)
        server = Server(session, args.port)
        stack.callback(server.stop)
        for signum in (signal.SIGINT, signal.SIGTERM):
            stack.callback(signal.signal, signum, signal.signal(signum, lambda *_: stop.set()))
        session.start()
        server.start()
        print(f"design: {server.url}", flush=True)
        stack.callback(close_all, start_controllers(args, session))
        if not args.quiet:
            over = f" over {backdrop.name}" if backdrop.name else ""
            print(
                f"marblevideo: designing {args.ops}{over} at {server.url}; Ctrl-C to stop",
                file=sys.stderr,
                flush=True,
            )
        if not args.no_browser:
            webbrowser.open(server.url)
        stop.wait(args.duration)
    if not args.quiet:
        print(f"marblevideo: saved {args.ops}", file=sys.stderr, flush=True)
    return 0
