"""A video rendered in segments, in this process or on a Ray cluster, then
joined (:func:`render_split`).

The input is cut at its keyframes (:func:`marblevideo.jobs.segments.plan_segments`);
each segment is rendered by :func:`render_segment` through the normal decode
-> kernel -> encode pipeline into an MP4 in a temporary folder beside the
output (workers on other machines must see both paths: shared storage, at the
same path), and the segments are joined by packet copy with the source's
audio (:func:`~marblevideo.jobs.segments.join_segments`), atomically: on any
failure nothing is left at the output and the folder is removed.

Every frame is marbled at its own time on the whole input's clock, as in a
single render; a segment's first frame is drawn as the single render would
draw it (a frame at the time of the one shown before it is rendered first and
dropped, so the renderer reuses its maps exactly where the single render does).
Decoded frames then equal a single render's wherever the encoder is lossless
(``--crf 0`` with x264); timestamps and audio packets always do.

A recipe with ``motion``: a segment's strokes come from the frames before it, so
each segment starts its analysis early: its worker first shows the segment's
transform every frame before the segment (:func:`marblevideo.jobs.takes.watch_before`:
decoded, luma plane only, nothing marbled), and its motion then goes on exactly
as a single render's does there. The last segment's strokes are the whole
input's: the take (``automation``).
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path

from marblevideo.errors import MediaError, UsageError
from marblevideo.jobs.options import as_options
from marblevideo.jobs.pipeline import transcode
from marblevideo.jobs.route import Route
from marblevideo.jobs.segments import Segment, join_segments, plan_segments, segment_plan
from marblevideo.jobs.takes import start_take, take_document, watch_before, write_take
from marblevideo.jobs.transforms import PipelinedTransform
from marblevideo.marbler import Marbler, RecipeLike, as_recipe
from marblevideo.media.encode import plan_output
from marblevideo.media.formats import is_local
from marblevideo.media.inputs import Input, classify, name_kind
from marblevideo.media.output import check_output
from marblevideo.media.progress import Progress, progress_mode
from marblevideo.media.video import Stats, VideoOptions, job_notify
from marblevideo.recipe import Recipe
from marblevideo.scale.cluster import RayPool, SerialPool, require_ray
from marblevideo.signals.follow import check as check_signals
from marblevideo.signals.follow import follow

CLUSTERS = ("serial", "ray")
NOT_SPLIT = {"start": "--start", "end": "--end", "duration": "--duration", "fps": "--fps"}


@dataclass(frozen=True)
class SegmentJob:
    """What every segment of a job shares (small: sent to each worker)."""

    src: str
    recipe: Recipe
    options: dict  # VideoOptions fields of the encoder, size and walk


class Primed(PipelinedTransform):
    """A video transform whose first frame is preceded by one drawn at ``before``
    (and dropped): the renderer then knows the frame shown before it."""

    def __init__(self, transform: PipelinedTransform, before: float | None):
        self.transform, self.before = transform, before
        self.planar, self.moves, self.lattice = transform.planar, transform.moves, transform.lattice
        self.watches = transform.watches
        self._seen = None  # the frame watched, shown to the transform once primed

    def watch(self, frame, t: float) -> None:
        self._seen = (frame, t)

    def _primed(self, start: Callable[[float], Callable], t: float):
        """The frame at ``before`` drawn (with the motion of the frame before) and
        dropped, then the frame watched shown, then the frame at ``t`` started."""
        if self.before is not None:
            start(self.before)()
            self.before = None
        if self._seen is not None:
            self.transform.watch(*self._seen)
            self._seen = None
        return start(t)

    def start_rgba(self, frame, t: float, route: Route):
        return self._primed(lambda at: self.transform.start_rgba(frame, at, route), t)

    def start_i420(self, planes, t: float, src, route: Route):
        return self._primed(lambda at: self.transform.start_i420(planes, at, src, route), t)


def render_segment(
    job: SegmentJob, segment: Segment, dst: str, renderer=None
) -> tuple[int, list[str], list[dict]]:
    """Render ``segment`` of ``job`` to the MP4 ``dst`` (atomically); the frames
    written, the notices (which the job's driver tells, each once) and the motion
    strokes made up to the segment's end (the whole take in the last one)."""
    options = VideoOptions(**job.options)
    options.start, options.end = segment.start, segment.end
    options.audio, options.quiet, options.progress, options.overwrite = "none", True, "off", True
    options.notify = lambda message: None  # noted in the stats, told by the driver
    plan = segment_plan(plan_output(dst, options), dst)
    recipe = follow(job.recipe, job.src)  # the whole file's audio: every segment hears the same
    marbler = Marbler(
        recipe, renderer, fit=options.fit or "stretch", lattice=not options.exact_walk
    )
    transform = marbler.transform(options.size)
    if transform.watches:
        watch_before(job.src, transform, segment.start)
    primed = Primed(transform, segment.before)
    stats = transcode(job.src, dst, primed, options, plan=plan, pts_origin=segment.origin)
    strokes = transform.stirred.tracker.take() if transform.stirred is not None else []
    return stats.frames, stats.notes, strokes


def check_split(src, options: VideoOptions) -> Input:
    """``src`` classified, or UsageError where a job cannot be split: the input is
    not a video file, or an option would cut or retime it."""
    if name_kind(src) != "video" or not is_local(src):
        what = "a blank sheet" if src is None else src
        raise UsageError(f"--cluster: {what} is not a video file; segments are cut from one")
    if options.soundtrack is not None:
        raise UsageError(
            "--soundtrack: not with --cluster (segments are joined with the input's own audio; "
            "mux the sound into the input first)"
        )
    for name, flag in NOT_SPLIT.items():
        if getattr(options, name) is not None:
            raise UsageError(f"{flag}: not with --cluster (cut or convert the input first)")
    return classify(src)


def render_split(
    src: str | os.PathLike,
    recipe: RecipeLike,
    dst: str | os.PathLike,
    *,
    cluster: str = "ray",
    segments: int | None = None,
    jobs: int | None = None,
    device: str | None = None,
    options: VideoOptions | None = None,
    automation: str | os.PathLike | None = None,
    document: dict | None = None,
    **fields,
) -> Stats:
    """Render video ``src`` to ``dst`` in segments (see the module) on ``cluster``:
    "ray" (:class:`~marblevideo.scale.cluster.RayPool`: ``$RAY_ADDRESS``'s cluster or a
    local one, ``jobs`` workers) or "serial" (here, one segment after another).
    ``segments``: how many to cut (default: one per about 45 s); ``options`` (or
    ``fields``) as :func:`marblevideo.api.render_video`'s, but no ``start``, ``end``,
    ``duration`` or ``fps``; ``automation`` and ``document`` as there too.
    Returns the joined output's :class:`~marblevideo.media.video.Stats`.
    Raises UsageError before any work; MediaError naming a segment that failed."""
    began = time.monotonic()
    if cluster not in CLUSTERS:
        raise UsageError(f"--cluster: expected one of {', '.join(CLUSTERS)}, got {cluster!r}")
    opts = as_options(fields, "render_split", options)
    given, recipe = recipe, as_recipe(recipe)
    source = check_split(src, opts)
    check_signals(recipe, source)
    recipe = recipe.bind(None)  # each worker analyses the input's audio itself
    plan = plan_output(dst, opts)
    segment_plan(plan, dst)
    dst = check_output(dst, opts.overwrite, source.names)
    others = [dst, *source.names, recipe.source]
    document = start_take(automation, given, document, opts.overwrite, others)
    source = source.checked()
    if cluster == "ray":
        require_ray()
    parts = plan_segments(src, segments)
    if segments and len(parts) < segments:
        notify = job_notify(opts, Stats())
        notify(f"{src}: {segments} segments asked; its keyframes allow {len(parts)}")
    job = SegmentJob(str(source.path.resolve()), recipe, _shared(opts, plan))
    make_pool = partial(RayPool, jobs, device) if cluster == "ray" else partial(SerialPool, device)
    stats, strokes = _run_segments(make_pool, job, parts, (src, dst), plan, opts)
    if automation is not None:
        write_take(automation, take_document(document, strokes), opts.overwrite)
    stats.seconds = time.monotonic() - began
    return stats


def _shared(opts: VideoOptions, plan) -> dict:
    """The segments' encoder options: the output's encoder and pixel format (from
    its extension), whatever the segments' own extension would give."""
    keys = ("crf", "preset", "size", "fit", "verbose", "exact_walk")
    shared = {k: getattr(opts, k) for k in keys}
    shared.update(codec=plan.codec, pix_fmt=plan.pix_fmt, encoder_opts=dict(opts.encoder_opts))
    return shared


def _run_segments(make_pool, job: SegmentJob, parts: list[Segment], src_dst, plan, opts):
    """Render every segment into a temporary folder beside ``dst`` on the pool
    ``make_pool()`` starts, then join them with the audio of ``src`` into ``dst``
    here."""
    src, dst = src_dst
    try:
        folder = Path(tempfile.mkdtemp(prefix=f".{dst.stem}.segments.", dir=dst.parent.resolve()))
    except OSError as exc:
        raise MediaError(f"{dst}: cannot write in {dst.parent}: {exc.strerror}") from None
    pool = None
    try:
        pool = make_pool()
        paths = [str(folder / f"{s.index:05d}.mp4") for s in parts]
        calls = [(job, s, path) for s, path in zip(parts, paths, strict=True)]
        notes, strokes = run_calls(pool, calls, parts, progress_mode(opts.progress, opts.quiet))
        pool.close()  # the workers' part is done: the join runs here
        pool = None
        notify = job_notify(opts, Stats())
        for note in notes:
            notify(note)
        pieces = [(Path(p), s.origin) for p, s in zip(paths, parts, strict=True)]
        stats = join_segments(src, pieces, dst, plan, opts)
        stats.notes[:0] = notes
    finally:
        if pool is not None:
            pool.close()
        shutil.rmtree(folder, ignore_errors=True)
    return stats, strokes


def run_calls(pool, calls: list[tuple], parts: list[Segment], progress: str):
    """Every segment's call on ``pool``, with a bar of segments: (their notices, each
    once; the last segment's motion strokes, the whole take); MediaError naming the
    first segment that failed."""
    notes: dict[str, None] = {}
    strokes: list[dict] = []
    with Progress(len(calls), progress, unit="segment") as bar:
        for index, result in pool.run(render_segment, calls, [str(s) for s in parts]):
            if isinstance(result, Exception):
                raise MediaError(f"{parts[index]} failed: {result}")
            notes.update(dict.fromkeys(result[1]))
            if parts[index].end is None:
                strokes = result[2]
            bar.update()
    return list(notes), strokes
