"""The Python API: a recipe bound to a renderer, and whole jobs on files.

Times are seconds; images are RGBA uint8 arrays (H, W, 4). A still is rendered
at ``time`` or, without it, at the recipe's end (the finished design).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from marblevideo.errors import RecipeError, UsageError
from marblevideo.frame import Geometry, geometry
from marblevideo.images import read_image, write_image
from marblevideo.output import atomic_output, check_output
from marblevideo.recipe import Recipe, load_recipe, parse_recipe
from marblevideo.renderer import Renderer

RecipeLike = Recipe | dict | str | os.PathLike


def as_recipe(recipe: RecipeLike) -> Recipe:
    """A Recipe from a Recipe, a dict (validated) or a path to a JSON file."""
    if isinstance(recipe, Recipe):
        return recipe
    if isinstance(recipe, dict):
        return parse_recipe(recipe, "<recipe>")
    return load_recipe(recipe)


def blank_size(recipe: Recipe) -> tuple[int, int]:
    """Default output size of a blank sheet: the canvas, rounded."""
    cw, ch = blank_canvas(recipe)
    return max(1, round(cw)), max(1, round(ch))


def blank_canvas(recipe: Recipe) -> tuple[float, float]:
    if recipe.canvas is None:
        raise RecipeError(recipe.source, "canvas", "a blank-sheet recipe must give canvas [W, H]")
    return recipe.canvas


class Marbler:
    """A recipe bound to an OpenCL renderer.

    ``render`` makes one frame; ``transform`` returns the callable that the
    video pipeline calls per frame (RGBA frame, time) -> RGBA frame.
    """

    def __init__(
        self, recipe: RecipeLike, renderer: Renderer | None = None, device: str | None = None
    ):
        self.recipe = as_recipe(recipe)
        self.renderer = renderer or Renderer(device)
        self._geometry: dict[tuple, Geometry] = {}

    def geometry(
        self,
        out_size: tuple[int, int],
        input_size: tuple[int, int] | None,
        view: tuple[float, float, float, float] | None = None,
    ) -> Geometry:
        key = (out_size, input_size, view)
        geom = self._geometry.get(key)
        if geom is None:
            canvas = self.recipe.canvas or input_size or blank_canvas(self.recipe)
            geom = self._geometry[key] = geometry(canvas, out_size, input_size, view)
        return geom

    def render(
        self,
        image: np.ndarray | None = None,
        time: float | None = None,
        size: tuple[int, int] | None = None,
        view: tuple[float, float, float, float] | None = None,
    ) -> np.ndarray:
        """One marbled frame of ``image`` (or of the blank sheet) at ``time``."""
        t = self.recipe.end_time() if time is None else float(time)
        input_size = None if image is None else (image.shape[1], image.shape[0])
        if size is None:
            size = input_size or blank_size(self.recipe)
        canvas = self.recipe.canvas or input_size or blank_canvas(self.recipe)
        spec = self.recipe.at(t, canvas)
        return self.renderer.render(spec, self.geometry(size, input_size, view), image)

    def transform(
        self, size: tuple[int, int] | None = None
    ) -> Callable[[np.ndarray, float], np.ndarray]:
        """(frame, t) -> marbled frame, for the video pipeline."""

        def marble(frame: np.ndarray, t: float) -> np.ndarray:
            return self.render(frame, t, size)

        return marble


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
) -> Path:
    """Render an image file (or a blank sheet) to an image file, atomically."""
    recipe = as_recipe(recipe)
    dst = Path(dst)
    inputs = [src] if src is not None else []
    if src is None:
        blank_canvas(recipe)
    check_output(dst, overwrite, inputs)
    image, has_alpha = (None, False) if src is None else read_image(src)
    marbler = Marbler(recipe, device=device)
    out = marbler.render(image, time, size, view)
    with atomic_output(dst, overwrite, inputs) as tmp:
        write_image(tmp, out, alpha=has_alpha, fmt=dst.suffix, name=dst)
    return dst


def parse_size(text: str) -> tuple[int, int]:
    """'WxH' -> (W, H), each 1..32768."""
    parts = text.lower().split("x")
    if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
        raise UsageError(f"--size: expected WxH such as 1280x720, got {text!r}")
    w, h = (int(p) for p in parts)
    if not (0 < w <= 32768 and 0 < h <= 32768):
        raise UsageError(f"--size: each side must be 1..32768, got {text!r}")
    return w, h


def _video_options(options: dict):
    from marblevideo.video import VideoOptions

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
    fps: float = 30.0,
    **options,
):
    """Marble every frame of the video ``src`` into ``dst`` at its own time, keeping
    audio and timing; with ``src=None`` render the recipe's process on a blank sheet
    for ``duration`` seconds (default: the whole animation plus one second) at ``fps``.
    ``options`` are the fields of :class:`marblevideo.video.VideoOptions`
    (codec, crf, preset, pix_fmt, encoder_opts, audio, start, end, size, overwrite,
    quiet, progress). Returns the job's :class:`marblevideo.video.Stats`."""
    from marblevideo.video import render_blank, transcode

    recipe = as_recipe(recipe)
    opts = _video_options(options)
    if src is None:
        blank_canvas(recipe)
        duration = recipe.end_time() + 1.0 if duration is None else duration
        marbler = Marbler(recipe, device=device)
        size = opts.size or blank_size(recipe)
        return render_blank(dst, lambda t: marbler.render(None, t, size), duration, fps, opts)
    marbler = Marbler(recipe, device=device)
    return transcode(src, dst, marbler.transform(opts.size), opts)


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
    from marblevideo.video import iter_frames

    marbler = Marbler(recipe, device=device)
    opts = _video_options({"start": start, "end": end})
    yield from iter_frames(src, marbler.transform(size), opts)
