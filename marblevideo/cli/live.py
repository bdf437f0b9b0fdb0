"""``marblevideo live``: marble a camera, a file/URL or a test pattern in real time
(:mod:`marblevideo.live`).

Stopping: ``--duration``, the end of a file source without ``--loop``, or
SIGINT (Ctrl-C) / SIGTERM, which are the normal end of a live session: the
recording so far is finalized and kept and the exit status is 0. A second
Ctrl-C while finalizing aborts (exit 130, no recording left).
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading

from marblevideo.cli.arguments import (
    Parser,
    add_encoder_arguments,
    add_log_arguments,
    configure_logging,
    parse_size,
)
from marblevideo.cli.controllers import (
    add_controller_arguments,
    check_controllers,
    close_all,
    report_controllers,
    start_controllers,
    write_take,
)
from marblevideo.cli.live_outputs import (
    add_output_arguments,
    recorder_for,
    split_outputs,
    streamers_for,
)
from marblevideo.errors import MarbleError, UsageError
from marblevideo.limits import DEFAULT_FPS, DEFAULT_PORT
from marblevideo.live.ndi import NdiSender, check_ndi
from marblevideo.live.session import LiveSession
from marblevideo.live.sources import open_source
from marblevideo.live.vcam import VCAM_HELP, VirtualCamera
from marblevideo.signals.live import live_audio


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="marblevideo live",
        description="Marble a camera, a video file or URL, or a test pattern in real time; "
        "preview it in a browser, send it to a virtual camera, record it.",
        epilog="examples:\n"
        "  marblevideo live test --ops samples/swirl.json --preview\n"
        "  marblevideo live 0 --ops samples/swirl.json --vcam\n"
        "  marblevideo live clip.mp4 --loop --ops swirl.json --preview -o take1.mp4\n"
        "  marblevideo live 0 --ops mine.json --preview --osc 9000 --automation take.json\n"
        "  marblevideo live 0 --ops swirl.json -o take.mp4 -o rtmp://127.0.0.1/live/KEY\n"
        "  marblevideo live 0 --ops swirl.json --ndi marbled\n\n"
        "Ctrl-C (SIGINT) or SIGTERM ends a session normally: the recording is kept, exit 0.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "source",
        nargs="?",
        help="camera index or /dev/videoN, a video file or URL, or 'test' (default: camera 0)",
    )
    p.add_argument("--source", dest="source_opt", metavar="SOURCE", help="same as SOURCE")
    p.add_argument(
        "--ops", required=True, metavar="RECIPE", help="recipe JSON file (watched) or preset"
    )
    p.add_argument(
        "--preview", action="store_true", help="serve the designer's page in live mode on 127.0.0.1"
    )
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"preview port ({DEFAULT_PORT})")
    p.add_argument("--vcam", action="store_true", help="send frames to a virtual camera")
    add_output_arguments(p)
    p.add_argument("-y", "--overwrite", action="store_true", help="replace existing outputs")
    p.add_argument("--size", metavar="WxH", help="test pattern size, or the size asked of a camera")
    p.add_argument(
        "--fps", type=float, help=f"test pattern rate ({DEFAULT_FPS:g}), or asked of a camera"
    )
    p.add_argument("--loop", action="store_true", help="file sources: start again at the end")
    p.add_argument(
        "--soundtrack",
        metavar="FILE",
        help="a sound file that audio signals follow from the session's start (default: a "
        "file source's own audio, at each frame's time)",
    )
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds")
    p.add_argument("--device", help="OpenCL device: P:D, a name, see `marblevideo devices`")
    p.add_argument(
        "--preview-width", type=int, metavar="W", help="encode the preview at most W pixels wide"
    )
    p.add_argument("--jpeg-quality", type=int, default=80, help="preview JPEG quality (80)")
    add_controller_arguments(p)
    p.add_argument(
        "--exact-walk",
        action="store_true",
        help="walk every subsample of animated frames (default: interpolate the map from a "
        "walked lattice where it is smooth)",
    )
    add_log_arguments(p)
    v = p.add_argument_group("recording (as the file mode)")
    add_encoder_arguments(v, preset_default="here: veryfast, for real time")
    return p


def run_live(argv: list[str]) -> int:
    """The ``live`` command; returns the exit status (MarbleError propagates)."""
    args = build_parser().parse_args(argv)
    configure_logging(args.verbose)
    spec, recipe, size = _checked(args)
    recorder = recorder_for(args, args.output) if args.output else None  # checked up front
    streams = streamers_for(args)
    live = _Live(args, open_source(spec, size, args.fps, args.loop), recorder, streams)
    try:
        live.open(recipe)
        live.session.run(args.duration)
        live.ok = True
        if args.automation:
            write_take(args, live.session)
    finally:
        live.close()
    if not args.quiet:
        print(f"marblevideo: {live.session.summary()}", file=sys.stderr, flush=True)
        report_controllers(args, live.session)
        if recorder is not None:
            print(f"marblevideo: wrote {args.output}", file=sys.stderr, flush=True)
    return 0


def _checked(args: argparse.Namespace):
    """(the source's spec, the recipe, the size or None): every option checked
    before anything opens (a bad recipe or option exits 2)."""
    from marblevideo.bundled import recipe_file
    from marblevideo.cli.working_copy import copy_preset, plan_working_copy
    from marblevideo.recipe import load_recipe

    if args.source and args.source_opt and args.source != args.source_opt:
        raise UsageError("give the source once: SOURCE or --source")
    args.output, args.streams = split_outputs(args.outputs)
    preset = None
    if args.preview:  # the page edits the recipe: a preset's name edits a copy of it
        args.ops, preset = plan_working_copy(args.ops, args.overwrite)
    else:  # only read: a preset's file, when no file of that name exists
        args.ops = recipe_file(args.ops)
    recipe = load_recipe(preset or args.ops)
    size = parse_size(args.size) if args.size else None
    for flag, value in (("--fps", args.fps), ("--duration", args.duration)):
        if value is not None and value <= 0:
            raise UsageError(f"{flag}: must be > 0, got {value}")
    if not 0 <= args.port <= 65535:
        raise UsageError(f"--port: must be 0..65535, got {args.port}")
    if not 1 <= args.jpeg_quality <= 100:
        raise UsageError(f"--jpeg-quality: must be 1..100, got {args.jpeg_quality}")
    if args.preview_width is not None and args.preview_width < 16:
        raise UsageError(f"--preview-width: must be >= 16, got {args.preview_width}")
    if args.vcam:
        try:
            import pyvirtualcam  # noqa: F401 - checked before anything opens
        except ImportError:
            raise MarbleError(f"--vcam needs pyvirtualcam: {VCAM_HELP}") from None
    if args.ndi is not None:
        check_ndi(args.ndi)
    check_controllers(args, recipe)
    if preset is not None:
        copy_preset(preset, args.ops, args.quiet)
    return args.source_opt or args.source or "0", recipe, size


class _Live:
    """One live run's parts: the source, the session that marbles it, and what
    listens and watches (preview server, controllers, signal handlers); :meth:`close`
    ends them in order, whatever was opened."""

    def __init__(self, args: argparse.Namespace, source, recorder, streams: list):
        self.args, self.source, self.recorder, self.streams = args, source, recorder, streams
        self.session = self.server = None
        self.listeners: list = []
        self.previous: dict[int, object] = {}
        self.stop = threading.Event()
        self.ok = False

    def on_signal(self, signum, frame):
        if self.stop.is_set():  # a second Ctrl-C while finishing: abort
            raise KeyboardInterrupt
        self.stop.set()
        if self.session is not None:
            self.session.stop_event.set()

    def open(self, recipe) -> None:
        args, source = self.args, self.source
        audio, by_frame = live_audio(recipe, source, args.soundtrack)
        self.session = session = LiveSession(
            args.ops,
            source,
            device=args.device,
            jpeg=args.preview,
            preview_width=args.preview_width,
            jpeg_quality=args.jpeg_quality,
            quiet=args.quiet,
            audio=audio,
            audio_by_frame=by_frame,
            lattice=not args.exact_walk,
        )
        width, height = source.size
        if args.vcam:
            session.vcam = VirtualCamera(width, height, source.fps)
        if self.recorder is not None:
            self.recorder.start(width, height, source.fps)
            session.recorder = self.recorder
        if args.ndi is not None:
            session.ndi = NdiSender(args.ndi, width, height, source.fps)
            notify(f"NDI: sending as {session.ndi.full_name}", args.quiet)
        for stream in self.streams:
            stream.start(width, height, source.fps)
        session.streams = self.streams
        if args.preview:
            self.server = _preview(session, args.port)
        self.listeners = start_controllers(args, session)
        for signum in (signal.SIGINT, signal.SIGTERM):
            self.previous[signum] = signal.signal(signum, self.on_signal)
        if not args.quiet:
            print(
                f"marblevideo: live from {source.name} ({width}x{height}); Ctrl-C to stop",
                file=sys.stderr,
                flush=True,
            )

    def close(self) -> None:
        close_all(self.listeners)
        if self.server is not None:
            self.server.stop()
        if self.session is not None:
            self.session.close()
        else:
            self.source.stop()
        if self.session is not None and self.session.vcam is not None:
            self.session.vcam.close()
        if self.session is not None and self.session.ndi is not None:
            self.session.ndi.close()
        for stream in self.streams:
            stream.close()
        if self.recorder is not None:
            self.recorder.close(ok=self.ok)
        for signum, handler in self.previous.items():
            signal.signal(signum, handler)


def notify(message: str, quiet: bool) -> None:
    if not quiet:
        print(f"marblevideo: {message}", file=sys.stderr, flush=True)


def _preview(session: LiveSession, port: int):
    """The designer's page, live, served on ``port`` (started; its URL printed)."""
    from marblevideo.design.live import LiveDesign
    from marblevideo.serve.server import Server

    server = Server(LiveDesign(session), port)  # the designer, live
    server.start()
    print(f"preview: {server.url}", flush=True)
    return server
