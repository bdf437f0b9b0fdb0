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
from marblevideo.limits import MAX_FPS, MAX_SECONDS
from marblevideo.media.inputs import Input
from marblevideo.media.video import VideoOptions

#: The kinds of input (:mod:`marblevideo.media.inputs`) marbled frame by frame.
VIDEO_KINDS = ("video", "sequence")


def positive(flag: str, value: float | None, limit: float, name: str, unit: str) -> None:
    """UsageError for a rate or a length given that is not > 0, or over ``limit``
    (called ``name`` in :mod:`marblevideo.limits`; in ``unit``)."""
    if value is not None and not value > 0:
        raise UsageError(f"{flag}: must be > 0, got {value:g}")
    if value is not None and value > limit:
        raise UsageError(f"{flag}: {value:g} {unit} is over the limit of {limit:g} {unit} ({name})")


def frame_rate(flag: str, value: float | None) -> None:
    """UsageError for a frame rate given that is not in (0, MAX_FPS]."""
    positive(flag, value, MAX_FPS, "MAX_FPS", "fps")


def moment(flag: str, value: float | None) -> None:
    """UsageError for a time given (seconds) that is not in [0, MAX_SECONDS]."""
    if value is not None and not value >= 0:
        raise UsageError(f"{flag}: must be >= 0 seconds, got {value:g}")
    if value is not None and value > MAX_SECONDS:
        raise UsageError(
            f"{flag}: {value:g} s is over the limit of {MAX_SECONDS:g} s (MAX_SECONDS)"
        )


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


def video_options(source: Input, options: VideoOptions, recipe=None) -> VideoOptions:
    """``options`` checked for a job on ``source``: ``fps`` and ``duration`` > 0 and
    within the limits, a range (``start``, ``end``) too, and only on a video or
    image sequence, with ``duration`` or ``end``, not both; a video's ``duration``
    returned as its ``end``. A still animated by ``recipe`` (where given): its
    length within the limit (:func:`sheet_duration`)."""
    frame_rate("--fps", options.fps)
    positive("--duration", options.duration, MAX_SECONDS, "MAX_SECONDS", "s")
    moment("--start", options.start)
    moment("--end", options.end)
    if source.kind not in VIDEO_KINDS:
        what = "a blank sheet" if source.kind == "blank" else f"{source.name}, a still"
        for flag, value in (("--start", options.start), ("--end", options.end)):
            if value is not None:
                raise UsageError(f"{flag}: {what} has no timeline; use --duration")
        if recipe is not None:
            sheet_duration(recipe, options)
        return options
    if options.duration is None:
        return options
    if options.end is not None:
        raise UsageError("--duration and --end: give one")
    end = (options.start or 0) + options.duration
    return dataclasses.replace(options, end=end, duration=None)


def sheet_duration(recipe, options: VideoOptions) -> float:
    """How long a still (or a blank sheet) animated lasts: ``duration``, else the
    recipe's animation (healing included) plus one second; UsageError where the
    recipe's is over MAX_SECONDS (its times may reach 1e30)."""
    if options.duration is not None:
        return options.duration
    duration = recipe.settled_time() + 1.0
    if duration > MAX_SECONDS:
        raise UsageError(
            f"{recipe.source}: the animation lasts {duration:g} s, over the limit of "
            f"{MAX_SECONDS:g} s (MAX_SECONDS); give --duration"
        )
    return duration
