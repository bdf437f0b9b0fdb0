"""Encoder settings tried before any work, and encoder libraries kept quiet.

:func:`check_encoder` opens a throw-away encoder context (64x64, the planned
pixel format, time base 1/25) with exactly the options the real encoder will
get, and turns FFmpeg's refusal into one :class:`UsageError` line naming the
flag that set the option (``--crf``, ``--preset``, ``--encoder-opt``):

- an option name the encoder does not have (FFmpeg would ignore it): refused,
  with close names offered (difflib); an option that exists but is not for
  encoding video (``skip_frame``, ``time_base``): refused too;
- a value the encoder refuses: the option is found by adding the given options
  one at a time to the defaults; the message lists the choices where known
  (x264/x265 presets and tunes: fixed lists below; FFmpeg's named constants
  otherwise), the range for a value out of it, else FFmpeg's own reason;
- a crf outside the encoder's scale (x264 and x265 take 0..51, though FFmpeg
  lets any float through and the library clamps it);
- a key inside ``x264-params``/``x265-params``/``svtav1-params`` that the
  library cannot parse (FFmpeg warns and goes on).

The probe takes 0.5-10 ms (x264 under 1 ms, x265 3 ms, SVT-AV1 6-10 ms). While
it runs, FFmpeg's log goes to a capture of this thread and file descriptor 2
points at ``os.devnull``: x264 and x265 print some complaints straight to it,
so for those milliseconds anything another thread writes to stderr is lost.

Quiet libraries (:func:`quiet_options`, :func:`quiet_environment`): unless
``verbose``, x265 gets ``log-level=none`` in ``x265-params`` (a ``log-level``
or ``log`` of the user's wins) and SVT-AV1 gets ``SVT_LOG=-1`` in the
environment, where none is set already. SVT-AV1 reads it once per process, at
its first encoder, so a verbose job after a quiet one in the same process
stays quiet. FFmpeg's own log is off unless PyAV's is turned on (``verbose``
turns it on for the job, :func:`library_logs`).
"""

from __future__ import annotations

import contextlib
import difflib
import os
import sys
from collections.abc import Iterator
from fractions import Fraction

import av
import av.logging

from marblevideo.errors import UsageError
from marblevideo.media.scheduling import ordinary_scheduling

# x264's and x265's own names (x264.h x264_preset_names / x264_tune_names,
# x265.h x265_preset_names / x265_tune_names, x264's profiles): FFmpeg passes
# these options on as strings and lists no choices for them
PRESETS = (
    "ultrafast",
    "superfast",
    "veryfast",
    "faster",
    "fast",
    "medium",
    "slow",
    "slower",
    "veryslow",
    "placebo",
)
CHOICES = {
    ("libx264", "preset"): PRESETS,
    ("libx265", "preset"): PRESETS,
    ("libx264", "tune"): (
        "film",
        "animation",
        "grain",
        "stillimage",
        "psnr",
        "ssim",
        "fastdecode",
        "zerolatency",
    ),
    ("libx265", "tune"): ("psnr", "ssim", "grain", "zerolatency", "fastdecode", "animation"),
    ("libx264", "profile"): ("baseline", "main", "high", "high10", "high422", "high444"),
}
# constant-quality scales narrower than FFmpeg's option range (x264, x265: -1..FLT_MAX)
CRF_RANGE = {"libx264": (0, 51), "libx265": (0, 51)}
# options whose value is a list of the library's own KEY=VALUE settings
PARAMS = {"libx264": "x264-params", "libx265": "x265-params", "libsvtav1": "svtav1-params"}
# library log switches: encoder -> (option, its keys for the level, quiet value)
QUIET_PARAMS = {"libx265": ("x265-params", ("log-level", "log"), "log-level=none")}
QUIET_ENV = {"libsvtav1": ("SVT_LOG", "-1")}  # -1: only untagged lines (none seen)

PROBE_SIDE = 64
_VIDEO_ENCODING = 1 | 16  # AV_OPT_FLAG_ENCODING_PARAM | AV_OPT_FLAG_VIDEO_PARAM


def option_table(codec: str) -> dict | None:
    """The encoder's video-encoding AVOptions, name -> PyAV's CodecOption (with
    ``min``, ``max``, ``choices``, ``type``), or None where PyAV cannot list them
    (PyAV before 17)."""
    ctx = av.CodecContext.create(codec, "w")
    try:
        found = ctx.supported_options
    except AttributeError:
        return None
    table = {}
    for option in (*found.generic, *found.private):
        if int(option.flags) & _VIDEO_ENCODING == _VIDEO_ENCODING:
            table.setdefault(option.name, option)
    return table


def quiet_options(codec: str, options: dict[str, str], verbose: bool) -> dict[str, str]:
    """``options`` with the library's own log turned off (x265), unless ``verbose``."""
    if verbose or codec not in QUIET_PARAMS:
        return options
    key, levels, quiet = QUIET_PARAMS[codec]
    given = options.get(key, "")
    keys = {part.partition("=")[0].strip() for part in given.split(":")}
    if keys & set(levels):
        return options
    return {**options, key: f"{quiet}:{given}" if given.strip() else quiet}


def quiet_environment(codec: str, verbose: bool) -> None:
    """Turn off a library's log that only the environment controls (SVT-AV1's
    ``SVT_LOG``), where the user has not set it; before its first encoder opens."""
    if not verbose and codec in QUIET_ENV:
        name, value = QUIET_ENV[codec]
        os.environ.setdefault(name, value)


@contextlib.contextmanager
def library_logs(verbose: bool) -> Iterator[None]:
    """FFmpeg's log on stderr for the block (its default callback) when ``verbose``."""
    if not verbose:
        yield
        return
    previous = av.logging.get_level()
    av.logging.restore_default_callback()
    try:
        yield
    finally:
        av.logging.set_level(previous)


def check_encoder(
    codec: str,
    pix_fmt: str,
    options: dict[str, str],
    given: dict[str, tuple[str, str]],
    table: dict | None,
) -> None:
    """Raise UsageError unless ``codec`` opens with ``pix_fmt`` and ``options``.

    ``given`` maps each option the user set to (the flag that set it, the value
    as given); the other options are marblevideo's defaults. ``table`` is
    :func:`option_table`'s."""
    if table is not None:
        for key, (flag, _) in given.items():
            if key not in table:
                raise UsageError(_unknown(flag, codec, key, table))
    if "crf" in options:
        _check_crf(codec, options["crf"], given.get("crf", ("--crf", options["crf"])), table)
    with _probing():
        failure, logs, left = _open(codec, pix_fmt, options)
        params = [k for k in given if k == PARAMS.get(codec)]
        if failure is None and not left and not (params and _warnings(logs)):
            return
        if left:
            key = next(iter(left))
            raise UsageError(_unknown(given.get(key, ("--encoder-opt", ""))[0], codec, key, table))
        base = {k: v for k, v in options.items() if k not in given}
        failure, logs, _ = _open(codec, pix_fmt, base)
        if failure is not None:
            reason = _reason(logs) or failure.strerror
            raise UsageError(f"--pix-fmt: {codec} cannot encode {pix_fmt}: {reason}")
        warned = len(_warnings(logs))
        for key, (flag, value) in given.items():
            base[key] = options[key]
            failure, logs, _ = _open(codec, pix_fmt, base)
            if failure is not None:
                raise UsageError(_refusal(flag, codec, key, value, failure, logs, table))
            if key in params and len(_warnings(logs)) > warned:
                warning = _warnings(logs)[warned]
                raise UsageError(f"{flag}: {codec} cannot use {key}={value}: {warning}")
            warned = len(_warnings(logs))
    settings = " ".join(f"{k}={v}" for k, (_, v) in given.items())
    raise UsageError(f"{codec} refuses these settings together: {settings}")


# ---------------------------------------------------------------------------- helpers


def _open(codec: str, pix_fmt: str, options: dict[str, str]):
    """Open a throw-away encoder: (the error or None, FFmpeg's log, options left unused)."""
    ctx = av.CodecContext.create(codec, "w")
    ctx.width = ctx.height = PROBE_SIDE
    ctx.pix_fmt = pix_fmt
    ctx.time_base = Fraction(1, 25)
    ctx.framerate = Fraction(25)
    ctx.options = dict(options)
    with av.logging.Capture() as logs, ordinary_scheduling():
        try:
            ctx.open()
        except (av.error.FFmpegError, ValueError) as exc:
            return exc, logs, {}
    return None, logs, dict(ctx.options)


@contextlib.contextmanager
def _probing() -> Iterator[None]:
    """FFmpeg's warnings captured (this thread's, by :func:`_open`; repeats too, as
    the search for the culprit repeats them), fd 2 silenced."""
    previous, repeats = av.logging.get_level(), av.logging.get_skip_repeated()
    av.logging.set_level(av.logging.WARNING)
    av.logging.set_skip_repeated(False)
    try:
        with stderr_silenced():
            yield
    finally:
        av.logging.set_skip_repeated(repeats)
        av.logging.set_level(previous)


@contextlib.contextmanager
def stderr_silenced() -> Iterator[None]:
    """File descriptor 2 pointed at os.devnull for the block (C libraries' own
    lines: encoder libraries, ALSA)."""
    with contextlib.suppress(AttributeError, ValueError, OSError):
        sys.stderr.flush()
    try:
        saved = os.dup(2)
    except OSError:  # no stderr at all: nothing to silence
        yield
        return
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def _warnings(logs) -> list[str]:
    return [_text(m) for level, _, m in logs if av.logging.ERROR < level <= av.logging.WARNING]


def _reason(logs) -> str | None:
    """FFmpeg's first error line (the expression parser's are less telling)."""
    for level, name, message in logs:
        if level <= av.logging.ERROR and name != "Eval":
            return _text(message)
    return None


def _text(message: str) -> str:
    return " ".join(message.split()).rstrip(".")


def _unknown(flag: str, codec: str, key: str, table: dict | None) -> str:
    line = f"{flag}: {codec} has no option {key!r} for encoding video"
    close = difflib.get_close_matches(key, list(table or ()), n=3, cutoff=0.6)
    if close:
        line += f" (did you mean {' or '.join(repr(name) for name in close)}?)"
    return line


def _check_crf(codec: str, value: str, given: tuple[str, str], table: dict | None) -> None:
    flag, shown = given
    option = (table or {}).get("crf")
    if codec in CRF_RANGE:
        low, high = CRF_RANGE[codec]
    elif option is not None:
        low, high = max(0.0, option.min), option.max  # -1 means "not set"
    else:
        return
    try:
        number = float(value)
    except ValueError:
        return  # the probe says what is wrong with it
    if not low <= number <= high:
        raise UsageError(f"{flag}: {codec} takes crf {_num(low)}..{_num(high)}, got {shown}")


def _refusal(flag, codec, key, value, failure, logs, table) -> str:
    option = (table or {}).get(key)
    choices = CHOICES.get((codec, key)) or tuple(c.name for c in getattr(option, "choices", ()))
    if isinstance(failure, OverflowError) and option is not None and option.max > option.min:
        return f"{flag}: {codec} takes {key} {_num(option.min)}..{_num(option.max)}, got {value}"
    if choices and value not in choices:
        return f"{flag}: {codec} has no {key} {value!r} ({', '.join(choices)})"
    reason = _reason(logs) or failure.strerror
    return f"{flag}: {codec} refused {key}={value}: {reason}"


def _num(x: float) -> str:
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:g}"
