"""A live session's ``-o`` outputs: at most one recording (a file) and any
number of streams to RTMP servers (:mod:`marblevideo.live.stream`), their
encoder settings checked before anything opens."""

from __future__ import annotations

import sys

from marblevideo.cli.arguments import parse_encoder_opts
from marblevideo.errors import UsageError
from marblevideo.live.stream import Streamer, check_stream_url, shown
from marblevideo.media.formats import is_url


def add_output_arguments(p) -> None:
    """``-o`` (repeatable: a recording, streams) and ``--ndi``."""
    p.add_argument(
        "-o",
        "--output",
        dest="outputs",
        action="append",
        default=[],
        metavar="OUTPUT",
        help="record what is shown (.mp4 .mov .mkv .webm), or stream it to an RTMP server "
        "(rtmp://HOST/APP/KEY: FLV, H.264 + AAC); give -o twice to stream and record at once",
    )
    p.add_argument(
        "--ndi",
        metavar="NAME",
        help="send frames as an NDI source called NAME (pip install 'marblevideo[ndi]')",
    )


def split_outputs(outputs: list[str]) -> tuple[str | None, list[str]]:
    """(the recording's file or None, the stream URLs) of the ``-o`` names."""
    streams = [name for name in outputs if is_url(name)]
    for url in streams:
        check_stream_url(url)
    if len(set(streams)) != len(streams):
        raise UsageError(f"-o: {shown(streams[0])} is given twice")
    files = [name for name in outputs if not is_url(name)]
    if len(files) > 1:
        raise UsageError(f"-o: one recording at a time, got {files[0]} and {files[1]}")
    return (files[0] if files else None), streams


def streamers_for(args) -> list[Streamer]:
    """A :class:`~marblevideo.live.stream.Streamer` per stream URL of ``args``, its
    encoder settings checked (the recording's flags, for FLV)."""

    def notify(message: str) -> None:
        if not args.quiet:
            print(f"marblevideo: {message}", file=sys.stderr, flush=True)

    return [Streamer(url, live_video_options(args, url, "flv"), notify) for url in args.streams]


def recorder_for(args, output: str):
    """The :class:`~marblevideo.live.recording.Recorder` of the file ``output``, with
    the encoder settings of ``args`` (checked)."""
    from marblevideo.live.recording import Recorder

    return Recorder(output, live_video_options(args, output))


def live_video_options(args, dst: str, format: str | None = None):
    """The encoder settings of a live output (a recording or a stream): the
    file mode's flags, with real-time defaults (x264/x265 veryfast, VP9 realtime)."""
    from marblevideo.media.encode import PRESET_CODECS, default_codec
    from marblevideo.media.video import VideoOptions

    opts = parse_encoder_opts(args.encoder_opt)
    codec = args.codec or default_codec(dst, format)
    preset = args.preset
    if preset is None and codec in PRESET_CODECS:
        preset = "veryfast"
    if codec == "libvpx-vp9":
        opts.setdefault("deadline", "realtime")
        opts.setdefault("cpu-used", "8")
    return VideoOptions(
        codec=args.codec,
        crf=args.crf,
        preset=preset,
        pix_fmt=args.pix_fmt,
        encoder_opts=opts,
        audio="none",
        overwrite=args.overwrite,
        quiet=args.quiet,
        verbose=args.verbose,
        progress="off",
        format=format,
    )
