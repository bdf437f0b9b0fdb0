"""Which options a job takes: every option given applies to the job the files
make, or the command exits 2 saying why (no option is ignored in silence). What
an option's value may be for the job's input (a range, a rate, a length) the job
checks itself (:mod:`marblevideo.jobs.options`).

Jobs: a *still* (an image output; from an image, a blank sheet, or a frame of
a video), a *video* (a video output; from a video, a still, or a blank sheet),
*vectors* (.svg, .pdf; from a blank sheet) and a *UV pass* (``--uv``).
Inputs: none (a blank sheet), a still image, a video (a file, an image
sequence, a URL) or ``-`` (standard input: a still or a video, known once read).
"""

from __future__ import annotations

import argparse

from marblevideo.errors import UsageError
from marblevideo.media.formats import output_kind
from marblevideo.media.inputs import name_kind

ENCODER_FLAGS = (
    ("codec", "--codec"),
    ("crf", "--crf"),
    ("preset", "--preset"),
    ("pix_fmt", "--pix-fmt"),
    ("encoder_opt", "--encoder-opt"),
)


def job_kind(args: argparse.Namespace) -> str:
    """ "still", "video", "vectors" or "uv"."""
    if args.uv:
        return "uv"
    kind = output_kind(args.output, args.format)
    return "vectors" if kind == "vector" else kind


def check_options(args: argparse.Namespace) -> tuple[str, str]:
    """(job, input kind: :func:`~marblevideo.media.inputs.name_kind`) of the
    command line; UsageError for an option given that the job does not take."""
    job, source = job_kind(args), name_kind(args.input)
    out = args.output
    if job != "video":
        for name, flag in (*ENCODER_FLAGS, ("audio", "--audio")):
            if getattr(args, name) not in (None, []):
                raise UsageError(f"{flag}: applies to video outputs; {out} is not one")
        for name, flag in (("start", "--start"), ("end", "--end")):
            if getattr(args, name) is not None:
                raise UsageError(f"{flag}: applies to video outputs; for {out} use --time")
        if args.duration is not None:
            raise UsageError(f"--duration: applies to video outputs; {out} is not one")
        for name, flag in (("exact_walk", "--exact-walk"), ("automation", "--automation")):
            if getattr(args, name, None):
                raise UsageError(f"{flag}: applies to video outputs; {out} is not one")
        if args.fps is not None and not (job == "still" and source == "sequence"):
            raise UsageError(
                f"--fps: applies to video outputs (and image-sequence inputs); {out} is not one"
            )
    else:
        if args.time is not None:
            raise UsageError(f"--time: makes stills; for {out} use --start and --end")
        soundtrack = getattr(args, "soundtrack", None)
        if source in ("blank", "image") and args.audio is not None and soundtrack is None:
            what = "a blank sheet" if source == "blank" else f"{args.input}, a still"
            raise UsageError(f"--audio: {what} has no audio (give one with --soundtrack)")
    if args.fit is not None:
        if job in ("vectors", "uv"):
            raise UsageError(f"--fit: places a raster's input or canvas; {out} is not one")
        if source == "blank" and args.view:
            raise UsageError("--fit: --view places a blank sheet's window itself; give one of them")
        if args.size is None:
            raise UsageError(
                "--fit: goes with --size (without it the output is the input's or canvas's size)"
            )
    if args.format is not None and job in ("vectors", "uv"):
        raise UsageError(f"--format: {out} is written as its extension says")
    check_cluster(args, job, source)
    return job, source


def check_cluster(args: argparse.Namespace, job: str, source: str) -> None:
    """``--cluster`` renders a video file to a video in segments; ``--segments``
    and ``--jobs`` go with it; nothing that cuts or retimes the input does."""
    if args.cluster is None:
        for name, flag in (("segments", "--segments"), ("jobs", "--jobs")):
            if getattr(args, name) is not None:
                raise UsageError(f"{flag}: goes with --cluster ray")
        return
    if job != "video" or source != "video":
        what = {"blank": "a blank sheet", "stdin": "standard input"}.get(source, args.input)
        raise UsageError(f"--cluster: renders a video file to a video in segments; not {what}")
    for name, flag in (("start", "--start"), ("end", "--end"), ("duration", "--duration"),
                       ("fps", "--fps")):  # fmt: skip
        if getattr(args, name) is not None:
            raise UsageError(f"{flag}: not with --cluster (cut or convert the input first)")
