"""A video job's options, checked once and in the command line's words, whoever
asks: ``marblevideo render`` builds a :class:`~marblevideo.media.video.VideoOptions`
from its flags, :func:`marblevideo.api.render_video` and
:func:`marblevideo.scale.segmented.render_split` from their keywords
(:func:`as_options`), and each job checks it against its input once
(:func:`video_options`). What needs no input (the range's order, the audio and
progress modes, the size) is checked where the output is planned
(:func:`marblevideo.media.encode.plan_output`); the soundtrack where audio signals
are bound (:func:`marblevideo.signals.follow.check`)."""

from __future__ import annotations

import dataclasses

from marblevideo.errors import UsageError
from marblevideo.media.inputs import Input
from marblevideo.media.video import VideoOptions

#: The kinds of input (:mod:`marblevideo.media.inputs`) marbled frame by frame.
VIDEO_KINDS = ("video", "sequence")


def positive(flag: str, value: float | None) -> None:
    """UsageError for a rate or a length given that is not > 0."""
    if value is not None and not value > 0:
        raise UsageError(f"{flag}: must be > 0, got {value:g}")


def as_options(fields: dict, caller: str, options: VideoOptions | None = None) -> VideoOptions:
    """:class:`VideoOptions` of an API call's keywords (``options`` where it was
    given one instead); UsageError naming ``caller`` and the keywords it does not
    know, or both given."""
    given = sorted(k for k, v in fields.items() if v is not None)
    if options is not None:
        if given:
            raise UsageError(f"{caller}: give options or keywords ({', '.join(given)}), not both")
        return options
    names = {f.name for f in dataclasses.fields(VideoOptions)}
    unknown = sorted(set(fields) - names)
    if unknown:
        raise UsageError(f"{caller}: unknown options {', '.join(unknown)}")
    return VideoOptions(**fields)


def video_options(source: Input, options: VideoOptions) -> VideoOptions:
    """``options`` checked for a job on ``source``: ``fps`` and ``duration`` > 0; a
    range (``start``, ``end``) only on a video or image sequence, with ``duration``
    or ``end``, not both; a video's ``duration`` returned as its ``end``."""
    positive("--fps", options.fps)
    positive("--duration", options.duration)
    if source.kind not in VIDEO_KINDS:
        what = "a blank sheet" if source.kind == "blank" else f"{source.name}, a still"
        for flag, value in (("--start", options.start), ("--end", options.end)):
            if value is not None:
                raise UsageError(f"{flag}: {what} has no timeline; use --duration")
        return options
    if options.duration is None:
        return options
    if options.end is not None:
        raise UsageError("--duration and --end: give one")
    end = (options.start or 0) + options.duration
    return dataclasses.replace(options, end=end, duration=None)
