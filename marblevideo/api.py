"""The Python API: whole jobs on files, and single images.

PyAV and OpenCV are imported by the jobs that read or write video (and follow
an input's motion) only: a still of an image or of a blank sheet loads neither.

Times are seconds; images are RGBA uint8 arrays (H, W, 4). A still is rendered
at ``time`` or, without it, at the recipe's end (the finished design). Every
job checks its output, then its input, before OpenCL starts.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from marblevideo.errors import UsageError
from marblevideo.jobs.options import (
    VIDEO_KINDS,
    as_options,
    frame_rate,
    moment,
    sheet_duration,
    video_options,
)
from marblevideo.limits import DEFAULT_FPS, DEFAULT_TOLERANCE
from marblevideo.marbler import (
    Marbler,
    RecipeLike,
    SheetSource,
    as_recipe,
    blank_canvas,
    blank_size,
    fit_note,
)
from marblevideo.media.formats import (
    is_stdio,
    still_extension,
)
from marblevideo.media.images import encode_image, read_image, write_image
from marblevideo.media.inputs import Input, classify
from marblevideo.media.output import atomic_output, check_output
from marblevideo.media.progress import Progress
from marblevideo.media.tiled import TILED_ABOVE, can_stream, check_still_size, write_bands
from marblevideo.media.tiled import band_rows as tiled_rows
from marblevideo.media.video import VideoOptions
from marblevideo.opencl.program import Structure
from marblevideo.opencl.renderer import Renderer
from marblevideo.outputs.svg import VectorStats, design_svg, pdf_writer
from marblevideo.reference.motion import rest_note
from marblevideo.signals.follow import follow


def render_image(
    recipe: RecipeLike,
    image: np.ndarray | None = None,
    *,
    time: float | None = None,
    size: tuple[int, int] | None = None,
    view: tuple[float, float, float, float] | None = None,
    device: str | None = None,
) -> np.ndarray:
    """Marble one image (or a blank sheet when ``image`` is None); returns RGBA uint8."""
    return Marbler(recipe, device=device).render(image, time, size, view)


def render_still(
    src: str | os.PathLike | None,
    recipe: RecipeLike,
    dst: str | os.PathLike,
    *,
    time: float | None = None,
    size: tuple[int, int] | None = None,
    view: tuple[float, float, float, float] | None = None,
    fit: str | None = None,
    format: str | None = None,  # noqa: A002 - the option's name, as av.open's
    rate: float | None = None,
    overwrite: bool = False,
    device: str | None = None,
    progress: str = "off",
    band_rows: int | None = None,
    notify: Callable[[str], None] | None = None,
    renderer: Renderer | None = None,
    soundtrack: str | os.PathLike | None = None,
) -> Path | str:
    """Render a still (PNG, JPEG, TIFF, WebP) atomically, of an image file, of a
    blank sheet, or of one frame of a video (a frame grab: the frame shown at
    ``time``, default the first, marbled at its own time; from a file, an
    image sequence read at ``rate`` frames per second, ``-`` or a URL).
    ``src`` ``-`` is standard input (a still or a video); ``dst`` ``-`` is
    standard output, in ``format`` (png, jpeg, tiff). ``fit`` (stretch, crop,
    pad) places an input, or a blank sheet's canvas, of another aspect than
    ``size``; ``notify`` takes one-line notices (a stretched input, a fitted
    canvas, a still at the end of an animation that has come back to rest).
    ``renderer``: an OpenCL renderer to draw with (its context and built
    programs kept between jobs) instead of one of ``device``. Parameters that
    follow audio signals hear ``soundtrack`` (a sound file, its first sample at
    t = 0), else the input video's audio.

    PNG and TIFF outputs over :data:`marblevideo.media.tiled.TILED_ABOVE` pixels (or any,
    given ``band_rows``) are rendered in bands and written progressively, so
    their size is not bounded by memory; ``progress`` (a
    :class:`~marblevideo.media.progress.Progress` mode) reports the bands."""
    frame_rate("--fps", rate)
    moment("--time", time)
    recipe, ext, to_stdout = as_recipe(recipe), still_extension(dst, format), is_stdio(dst)
    source = classify(src)  # standard input: read to tell a still from a video
    dst, source = _check_still(source, recipe, dst, ext, size, overwrite)
    recipe = follow(recipe, source, soundtrack)
    marbler = Marbler(recipe, renderer, device=device, fit=fit)
    marbler.renderer.prebuild(Structure.of(recipe, source.kind != "blank"))  # while it loads
    image, has_alpha, time = still_input(source, time, rate)  # a grab's time: its frame's
    input_size = None if image is None else (image.shape[1], image.shape[0])
    if notify:
        _still_notes(notify, marbler, input_size, size, fit, time)
    out_size = size or input_size or blank_size(recipe)
    banded = can_stream(ext) and (band_rows or out_size[0] * out_size[1] > TILED_ABOVE)
    if to_stdout or not banded:
        out = marbler.render(image, time, size, view)
        return _write_still(out, dst, ext, has_alpha, overwrite, source.names)
    rows = band_rows or tiled_rows(out_size[0])
    with atomic_output(dst, overwrite, source.names) as tmp:
        bands = marbler.render_bands(image, time, out_size, view, rows)
        counted = _counted(bands, -(-out_size[1] // rows), progress)
        write_bands(tmp, ext, *out_size, 4 if has_alpha else 3, counted)
    return dst


def _check_still(source: Input, recipe, dst, ext: str, size, overwrite: bool):
    """(the output, the input checked): a still job's cheap checks, the output's
    then the input's, before the build (which an exit would wait for)."""
    if source.kind == "blank":
        blank_canvas(recipe)
    if size or source.kind == "blank":  # else the input's, within the input limit
        check_still_size(dst, ext, size or blank_size(recipe), not is_stdio(dst))
    return check_output(dst, overwrite, source.names), source.checked()


def _still_notes(notify, marbler: Marbler, input_size, size, fit, time) -> None:
    """Tell a stretched input or fitted canvas, a still at rest at the end, and a
    motion that a still cannot follow."""
    recipe = marbler.recipe
    notes = [fit_note(recipe, input_size, size, fit), motion_note(recipe, "a still")]
    if time is None:
        notes.append(rest_note(marbler.recipe, marbler.canvas(input_size)))
    for note in filter(None, notes):
        notify(note)


def motion_note(recipe, what: str) -> str | None:
    """The notice for a recipe's ``motion`` where nothing moves (``what``: a still, a
    blank sheet): it makes no stroke there."""
    if recipe.motion is None:
        return None
    return f"{recipe.source}: motion follows an input's movement; {what} has none"


def _write_still(out: np.ndarray, dst, ext: str, has_alpha: bool, overwrite: bool, inputs):
    """Write the still ``out`` to ``dst`` (a file, atomically, or ``-``)."""
    if is_stdio(dst):
        sys.stdout.buffer.write(encode_image(out, ext, has_alpha, "-"))
        sys.stdout.buffer.flush()
        return "-"
    with atomic_output(dst, overwrite, inputs) as tmp:
        write_image(tmp, out, alpha=has_alpha, fmt=ext, name=dst)
    return dst


def _counted(bands, total: int, progress: str):
    """``bands`` passed through, counted on a progress bar of ``total`` bands."""
    with Progress(total, progress, unit="band") as bar:
        for band in bands:
            yield band
            bar.update()


def still_input(
    src: str | os.PathLike | Input | None, time: float | None, rate: float | None
) -> tuple[np.ndarray | None, bool, float | None]:
    """(the RGBA image or None, whether it has alpha, the recipe's time) of a
    still's input: a still image, or the frame of a video shown at ``time``
    (whose own time the recipe takes)."""
    source = classify(src)
    if source.kind == "blank":
        return None, False, time
    if source.kind == "image":
        return (*read_image(source), time)
    from marblevideo.media.decode import grab_frame, open_input  # PyAV, for a frame grab

    with open_input(source, rate) as container:
        t, rgba = grab_frame(container, time)
    return rgba, False, t


def render_svg(
    recipe: RecipeLike,
    dst: str | os.PathLike,
    *,
    time: float | None = None,
    size: tuple[int, int] | None = None,
    tolerance: float = DEFAULT_TOLERANCE,
    overwrite: bool = False,
) -> VectorStats:
    """Write a blank-sheet design as SVG (:mod:`marblevideo.outputs.svg`), or as PDF
    when ``dst`` ends in .pdf (the same outlines through cairosvg, the optional
    extra ``pdf``), atomically. ``size`` is the page's width and height in pixels
    (default: the canvas); ``tolerance`` is in those pixels. Returns the
    :class:`~marblevideo.outputs.svg.VectorStats` (``bytes``: the SVG's)."""
    recipe = as_recipe(recipe)
    dst = Path(dst)
    canvas = blank_canvas(recipe)
    check_output(dst, overwrite)
    if not (tolerance > 0 and np.isfinite(tolerance)):
        raise UsageError(f"--tolerance: must be a number > 0 (pixels), got {tolerance}")
    pdf = dst.suffix.lower() == ".pdf"
    if pdf:
        to_pdf = pdf_writer()  # before the work: a missing extra is said at once
    t = recipe.end_time() if time is None else float(time)
    svg, stats = design_svg(recipe.at(t, canvas), size or blank_size(recipe), tolerance)
    with atomic_output(dst, overwrite) as tmp:
        if pdf:
            to_pdf(svg, tmp)
            stats.bytes = tmp.stat().st_size
        else:
            tmp.write_text(svg)
    return stats


def render_uv_pass(
    src: str | os.PathLike | None,
    recipe: RecipeLike,
    uv: str | os.PathLike,
    dst: str | os.PathLike,
    *,
    time: float | None = None,
    overwrite: bool = False,
) -> Path:
    """Render the design as seen through the UV pass file ``uv`` (see
    :mod:`marblevideo.outputs.uv`) to an image of the pass's size, atomically; pixels
    without surface are transparent where the format holds alpha."""
    from marblevideo.outputs.uv import read_uv, render_uv

    recipe = as_recipe(recipe)
    dst = Path(dst)
    inputs = [src, uv] if src is not None else [uv]
    if src is None:
        blank_canvas(recipe)
    check_output(dst, overwrite, inputs)
    u, v, surface = read_uv(uv)
    image = None if src is None else read_image(src)[0]
    input_size = None if image is None else (image.shape[1], image.shape[0])
    canvas = recipe.canvas or input_size
    t = recipe.end_time() if time is None else float(time)
    out = render_uv(recipe.at(t, canvas), u, v, surface, image)
    with atomic_output(dst, overwrite, inputs) as tmp:
        write_image(tmp, out, alpha=True, fmt=dst.suffix)
    return dst


def render_video(
    src: str | os.PathLike | None,
    recipe: RecipeLike,
    dst: str | os.PathLike,
    *,
    device: str | None = None,
    duration: float | None = None,
    fps: float | None = None,
    renderer: Renderer | None = None,
    options: VideoOptions | None = None,
    automation: str | os.PathLike | None = None,
    document: dict | None = None,
    **fields,
):
    """Write a video (any output of :mod:`marblevideo.media.formats`: a file, a GIF,
    an image sequence ``name_%04d.png``, or ``-`` for standard output in
    ``format``), atomically:

    - ``src`` a video (a file, an image sequence read at ``fps``, ``-`` or a
      URL): every frame marbled at its own time, audio and timing kept; with
      ``fps`` the frame rate is converted (ffmpeg's fps filter); ``duration``
      stops after that many seconds from ``start``;
    - ``src`` a still image (a file, or on ``-``): the recipe animated over it;
    - ``src=None``: the recipe's process on a blank sheet;

    the last two for ``duration`` seconds (default: the animation plus one
    second) at ``fps`` (default 30). ``options`` is a
    :class:`~marblevideo.media.video.VideoOptions` (as the command line builds), or
    ``fields`` are its fields as keywords (codec, crf, preset, pix_fmt,
    encoder_opts, audio, start, end, size, fit, format, overwrite, quiet,
    progress, verbose, notify, soundtrack: a sound file that replaces the
    input's audio, its first sample at t = 0, and that parameters following
    audio signals hear; exact_walk: animated frames walk every subsample
    instead of interpolating from a lattice). ``renderer`` as for
    :func:`render_still`. ``automation``: write the take there too
    (:mod:`marblevideo.jobs.takes`), of the recipe's JSON ``document`` (default:
    ``recipe``'s, a file or a dict). Returns the job's :class:`~marblevideo.media.video.Stats`."""
    from marblevideo.jobs.takes import start_take, take_document, write_take
    from marblevideo.media.encode import plan_output

    given, recipe = recipe, as_recipe(recipe)
    source = classify(src)  # standard input: read to tell a still from a video
    if source.kind == "blank":
        blank_canvas(recipe)
    fields = {**fields, "fps": fps, "duration": duration}
    opts = video_options(source, as_options(fields, "render_video", options), recipe)
    # the cheap checks first (the encoder is tried too; a build below delays an exit)
    plan = plan_output(dst, opts)
    check_output(dst, opts.overwrite, source.names)
    others = [dst, *source.names, recipe.source]
    document = start_take(automation, given, document, opts.overwrite, others)
    source = source.checked()
    recipe = follow(recipe, source, opts.soundtrack)  # the soundtrack checked there
    marbler = Marbler(recipe, renderer, device=device, fit=opts.fit, lattice=not opts.exact_walk)
    # the program builds (without the GIL) while the input opens
    marbler.renderer.prebuild(Structure.of(recipe, source.kind != "blank"))
    stats, stirred = _job(source, marbler, dst, opts, plan)
    if automation is not None:
        write_take(automation, take_document(document, stirred), opts.overwrite)
    return stats


def _job(source: Input, marbler: Marbler, dst, opts: VideoOptions, plan):
    """(the video job's stats, the motion that saw its frames: None without)."""
    from marblevideo.jobs.pipeline import transcode

    if source.kind not in VIDEO_KINDS:
        return _animated(source, marbler, dst, opts, plan), None
    transform = marbler.transform(opts.size)
    return transcode(source, dst, transform, opts, plan=plan), transform.stirred


def _animated(source: Input, marbler: Marbler, dst, opts: VideoOptions, plan):
    """A still (or a blank sheet) animated by the recipe for ``duration`` seconds
    (default: the animation, healing included, plus one second) at ``fps`` (default 30)."""
    from marblevideo.jobs.pipeline import render_sheet

    recipe = marbler.recipe
    image = None if source.kind == "blank" else read_image(source)[0]
    duration = sheet_duration(recipe, opts)
    size = opts.size or (blank_size(recipe) if image is None else image.shape[1::-1])
    frames = SheetSource(marbler, tuple(size), image)
    note = fit_note(recipe, None if image is None else image.shape[1::-1], opts.size, opts.fit)
    notes = (note,) if note else ()
    note = motion_note(recipe, "a blank sheet" if image is None else "a still")
    notes += (note,) if note else ()
    fps = opts.fps or DEFAULT_FPS
    return render_sheet(dst, frames, duration, fps, opts, plan=plan, notes=notes)


def marbled_frames(
    src: str | os.PathLike,
    recipe: RecipeLike,
    *,
    device: str | None = None,
    size: tuple[int, int] | None = None,
    start: float | None = None,
    end: float | None = None,
):
    """Iterate ``(t, rgba)``: the frames of video ``src`` marbled at their own times
    (audio signals follow its audio)."""
    from marblevideo.jobs.pipeline import iter_frames

    marbler = Marbler(follow(as_recipe(recipe), src), device=device)
    opts = VideoOptions(start=start, end=end)
    yield from iter_frames(src, marbler.transform(size), opts)
