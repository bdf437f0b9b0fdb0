"""``marblevideo CLIP --ops RECIPE -o rtmp://HOST/APP/KEY [--realtime]``: a file
render played at its own pace to a streaming server (restreaming a clip).

The clip is marbled as a live session's file source
(:mod:`marblevideo.cli.live`: frames released at their own times, the stream
surviving the server going away); the session ends at the clip's end. The
file mode's options that change frames or time (``--size``, ``--start``...)
are refused here, one line each.
"""

from __future__ import annotations

import argparse

from marblevideo.errors import UsageError
from marblevideo.media.formats import is_stream_url

#: The render options passed on to the live session: (dest, flag).
PASSED = (
    ("device", "--device"),
    ("soundtrack", "--soundtrack"),
    ("duration", "--duration"),
    ("codec", "--codec"),
    ("crf", "--crf"),
    ("preset", "--preset"),
    ("pix_fmt", "--pix-fmt"),
    ("automation", "--automation"),
)
#: The render options a stream does not take: (dest, flag).
REFUSED = (
    ("size", "--size"),
    ("fit", "--fit"),
    ("format", "--format"),
    ("time", "--time"),
    ("view", "--view"),
    ("tolerance", "--tolerance"),
    ("uv", "--uv"),
    ("start", "--start"),
    ("end", "--end"),
    ("fps", "--fps"),
    ("audio", "--audio"),
    ("cluster", "--cluster"),
)


def wants_realtime(args: argparse.Namespace) -> bool:
    """Whether a render goes out in real time: ``--realtime``, or a stream output."""
    return bool(args.realtime) or is_stream_url(args.output)


def render_realtime(args: argparse.Namespace) -> int:
    """Play ``args.input`` marbled at its own pace to ``args.output``; the exit status."""
    from marblevideo.cli.live import run_live

    if not is_stream_url(args.output):
        raise UsageError(f"--realtime: plays a render to a stream (rtmp://...), not {args.output}")
    if args.input is None:
        raise UsageError("--realtime: give a video to play (a file or URL)")
    for dest, flag in REFUSED:
        if getattr(args, dest) is not None:
            raise UsageError(f"{flag}: not with a stream played in real time")
    argv = [args.input, "--ops", args.ops, "-o", args.output]
    for dest, flag in PASSED:
        if getattr(args, dest) is not None:
            argv += [flag, str(getattr(args, dest))]
    for item in args.encoder_opt:
        argv += ["--encoder-opt", item]
    flags = (("quiet", "-q"), ("verbose", "--verbose"), ("exact_walk", "--exact-walk"))
    for dest, flag in (*flags, ("overwrite", "-y")):
        if getattr(args, dest):
            argv.append(flag)
    return run_live(argv)
