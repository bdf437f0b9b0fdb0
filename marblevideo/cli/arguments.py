"""What the commands share: one-line argparse errors (exit status 2), the
logging flags, the encoder flags, and the parsers of sizes and view windows."""

from __future__ import annotations

import argparse
import logging
import math
import sys
from collections.abc import Callable

from marblevideo.errors import MarbleError, UsageError
from marblevideo.limits import MAX_SIDE


def reported(prog: str, run: Callable[[], int]) -> int:
    """``run()``'s exit status, with a MarbleError as one line ``PROG: message`` on
    stderr and its exit code, and Ctrl-C as ``PROG: interrupted`` and 130."""
    try:
        return run()
    except MarbleError as exc:
        print(f"{prog}: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit status 2, and an option's value that
    starts with ``-`` taken as its value (``--size -1x10``, ``--view -5,0,9,9``: argparse
    would call it an unknown option and the option's value missing)."""

    def error(self, message: str):
        raise UsageError(f"{message} (see {self.prog} --help)")

    def parse_known_args(self, args=None, namespace=None):
        args = sys.argv[1:] if args is None else list(args)
        return super().parse_known_args(self._dashed_values(args), namespace)

    def _dashed_values(self, args: list[str]) -> list[str]:
        """``OPTION VALUE`` as ``OPTION=VALUE`` where the option takes one value and
        the value starts with one ``-`` and is no option (nor ``-``, standard i/o)."""
        out, i = [], 0
        while i < len(args):
            arg = args[i]
            if arg == "--":
                return out + args[i:]
            action = self._option_string_actions.get(arg)
            value = args[i + 1] if i + 1 < len(args) else ""
            if (
                action is not None
                and action.nargs is None
                and value.startswith("-")
                and not value.startswith("--")
                and value != "-"
                and value not in self._option_string_actions
            ):
                out.append(f"{arg}={value}")
                i += 2
                continue
            out.append(arg)
            i += 1
        return out


def add_log_arguments(parser) -> None:
    """-q and --verbose, shared by the commands."""
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar or notes")
    parser.add_argument(
        "--verbose",
        action="store_true",
        help="say which device and vector width render; show OpenCL build and encoder logs",
    )


def configure_logging(verbose: bool) -> None:
    """With ``verbose``, the ``marblevideo`` logger's DEBUG records go to stderr as
    ``marblevideo: ...`` lines (the renderer then builds with compiler warnings
    on and logs the build log); without, nothing is logged."""
    logger = logging.getLogger("marblevideo")
    for handler in list(logger.handlers):
        if getattr(handler, "marblevideo_cli", False):
            logger.removeHandler(handler)
    if not verbose:
        logger.setLevel(logging.NOTSET)
        return
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("marblevideo: %(message)s"))
    handler.marblevideo_cli = True
    logger.addHandler(handler)
    logger.setLevel(logging.DEBUG)


def add_encoder_arguments(group, preset_default: str) -> None:
    """The encoder flags shared by the file and live modes."""
    group.add_argument("--codec", help="video encoder (default: libx264; libvpx-vp9 for .webm)")
    group.add_argument("--crf", type=int, help="constant quality (default as ffmpeg: 23 for x264)")
    group.add_argument("--preset", help=f"x264/x265 preset (default {preset_default})")
    group.add_argument(
        "--pix-fmt", help="encoded pixel format (default yuv420p; GIF pal8, APNG rgb24)"
    )
    group.add_argument(
        "--encoder-opt",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="extra encoder option, repeatable (e.g. tune=film)",
    )


def parse_encoder_opts(items: list[str]) -> dict[str, str]:
    """--encoder-opt KEY=VALUE items as a dict."""
    opts = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise UsageError(f"--encoder-opt: expected KEY=VALUE, got {item!r}")
        opts[key] = value
    return opts


def parse_view(text: str) -> tuple[float, float, float, float]:
    """'X,Y,W,H' (canvas units) -> a view window; W and H > 0, all finite."""
    parts = text.split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 4 or not all(map(math.isfinite, values)):
        raise UsageError(
            f"--view: expected X,Y,W,H in canvas units such as 0,0,256,256, got {text!r}"
        )
    if values[2] <= 0 or values[3] <= 0:
        raise UsageError(f"--view: width and height must be > 0, got {text!r}")
    return values


def parse_size(text: str) -> tuple[int, int]:
    """'WxH' -> (W, H), each 1..MAX_SIDE."""
    parts = text.lower().split("x")
    if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
        raise UsageError(f"--size: expected WxH such as 1280x720, got {text!r}")
    w, h = (int(p) for p in parts)
    if not (0 < w <= MAX_SIDE and 0 < h <= MAX_SIDE):
        raise UsageError(f"--size: each side must be 1..{MAX_SIDE}, got {text!r}")
    return w, h
