"""The Python API: whole jobs on files, and single images.

Times are seconds; images are RGBA uint8 arrays (H, W, 4). A still is rendered
at ``time`` or, without it, at the recipe's end (the finished design). Every
job checks its output, then its input, before OpenCL starts.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from marblevideo.errors import UsageError
from marblevideo.limits import DEFAULT_FPS, DEFAULT_TOLERANCE
from marblevideo.marbler import (
    BlankFrames,
    Marbler,
    RecipeLike,
    as_recipe,
    blank_canvas,
    blank_size,
)
from marblevideo.media.images import read_image, write_image
from marblevideo.media.inputs import check_input
from marblevideo.media.output import atomic_output, check_output
from marblevideo.media.progress import Progress
from marblevideo.media.tiled import TILED_ABOVE, can_stream, write_bands
from marblevideo.media.tiled import band_rows as tiled_rows
from marblevideo.opencl.program import Structure
from marblevideo.outputs.svg import VectorStats, design_svg, pdf_writer


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
    overwrite: bool = False,
    device: str | None = None,
    progress: str = "off",
    band_rows: int | None = None,
) -> Path:
    """Render an image file (or a blank sheet) to an image file, atomically.

    PNG and TIFF outputs over :data:`marblevideo.media.tiled.TILED_ABOVE` pixels (or any,
    given ``band_rows``) are rendered in bands and written progressively, so
    their size is not bounded by memory; ``progress`` (a
    :class:`~marblevideo.media.progress.Progress` mode) reports the bands."""
    recipe = as_recipe(recipe)
    dst = Path(dst)
    inputs = [src] if src is not None else []
    if src is None:
        blank_canvas(recipe)
    check_output(dst, overwrite, inputs)
    if src is not None:  # before the build, which an early exit would wait for
        check_input(src, "an image")
    marbler = Marbler(recipe, device=device)
    marbler.renderer.prebuild(Structure.of(recipe, src is not None))  # while the image loads
    image, has_alpha = (None, False) if src is None else read_image(src)
    fmt = dst.suffix.lower()
    out_size = size or (
        (image.shape[1], image.shape[0]) if image is not None else blank_size(recipe)
    )
    if can_stream(fmt) and (band_rows or out_size[0] * out_size[1] > TILED_ABOVE):
        rows = band_rows or tiled_rows(out_size[0])
        total = -(-out_size[1] // rows)
        with (
            atomic_output(dst, overwrite, inputs) as tmp,
            Progress(total, progress, unit="band") as bar,
        ):

            def counted():
                for band in marbler.render_bands(image, time, out_size, view, rows):
                    yield band
                    bar.update()

            write_bands(tmp, fmt, *out_size, 4 if has_alpha else 3, counted())
        return dst
    out = marbler.render(image, time, size, view)
    with atomic_output(dst, overwrite, inputs) as tmp:
        write_image(tmp, out, alpha=has_alpha, fmt=dst.suffix, name=dst)
    return dst


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


def _video_options(options: dict):
    from marblevideo.media.video import VideoOptions

    try:
        return VideoOptions(**options)
    except TypeError as exc:
        raise UsageError(f"render_video: {exc}") from None


def render_video(
    src: str | os.PathLike | None,
    recipe: RecipeLike,
    dst: str | os.PathLike,
    *,
    device: str | None = None,
    duration: float | None = None,
    fps: float = DEFAULT_FPS,
    **options,
):
    """Marble every frame of the video ``src`` into ``dst`` at its own time, keeping
    audio and timing; with ``src=None`` render the recipe's process on a blank sheet
    for ``duration`` seconds (default: the whole animation plus one second) at ``fps``.
    ``options`` are the fields of :class:`marblevideo.media.video.VideoOptions`
    (codec, crf, preset, pix_fmt, encoder_opts, audio, start, end, size, overwrite,
    quiet, progress, verbose). Returns the job's :class:`marblevideo.media.video.Stats`."""
    from marblevideo.media.encode import plan_output
    from marblevideo.media.pipeline import render_blank, transcode

    recipe = as_recipe(recipe)
    if src is None:
        blank_canvas(recipe)
    opts = _video_options(options)
    # the cheap checks first (the encoder is tried too): an exit during the build
    # below waits for it
    plan = plan_output(dst, opts)
    check_output(dst, opts.overwrite, [] if src is None else [src])
    if src is not None:
        check_input(src, "a video")
    marbler = Marbler(recipe, device=device)
    # the program builds (without the GIL) while the video opens
    marbler.renderer.prebuild(Structure.of(recipe, src is not None))
    if src is None:
        duration = recipe.end_time() + 1.0 if duration is None else duration
        size = opts.size or blank_size(recipe)
        return render_blank(dst, BlankFrames(marbler, size), duration, fps, opts, plan=plan)
    return transcode(src, dst, marbler.transform(opts.size), opts, plan=plan)


def marbled_frames(
    src: str | os.PathLike,
    recipe: RecipeLike,
    *,
    device: str | None = None,
    size: tuple[int, int] | None = None,
    start: float | None = None,
    end: float | None = None,
):
    """Iterate ``(t, rgba)``: the frames of video ``src`` marbled at their own times."""
    from marblevideo.media.pipeline import iter_frames

    marbler = Marbler(recipe, device=device)
    opts = _video_options({"start": start, "end": end})
    yield from iter_frames(src, marbler.transform(size), opts)
