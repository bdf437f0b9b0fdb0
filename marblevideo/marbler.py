"""A recipe bound to an OpenCL renderer (:class:`Marbler`), and its forms for the
video pipeline: an input's frames (:class:`FrameTransform`) and a still's or a
blank sheet's (:class:`SheetSource`).

Times are seconds; images are RGBA uint8 arrays (H, W, 4). A still is rendered
at ``time`` or, without it, at the recipe's end (the finished design).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from marblevideo.errors import RecipeError, UsageError
from marblevideo.jobs.route import Route, frames_route
from marblevideo.jobs.transforms import PipelinedSource, PipelinedTransform
from marblevideo.media.yuv import YuvMatrix
from marblevideo.opencl.renderer import Renderer
from marblevideo.recipe import Recipe, load_recipe, parse_recipe
from marblevideo.recipe.frame import (
    FIT_MODES,
    FrameSpec,
    Geometry,
    canvas_note,
    geometry,
    stretch_note,
)

if TYPE_CHECKING:
    from marblevideo.motion import StirredRecipe

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


def fit_note(
    recipe: Recipe, input_size: tuple[int, int] | None, size: tuple[int, int] | None, fit
) -> str | None:
    """The notice for an output ``size`` of another aspect than what it shows, when
    no ``fit`` is given: an input stretched, or a blank sheet's canvas fitted."""
    if size is None or fit is not None:
        return None
    if input_size is not None:
        return stretch_note(input_size, size)
    return canvas_note(blank_canvas(recipe), size)


def image_size(image: np.ndarray | None) -> tuple[int, int] | None:
    """(w, h) of an image, or None for none (a blank sheet)."""
    return None if image is None else (image.shape[1], image.shape[0])


class Marbler:
    """A recipe bound to an OpenCL renderer.

    ``render`` makes one frame; ``transform`` returns the callable that the
    video pipeline calls per frame (RGBA frame, time) -> RGBA frame. ``fit``
    (:data:`~marblevideo.recipe.frame.FIT_MODES`) says how an input of another
    aspect than the output fills it (default: stretched), or a blank sheet's
    canvas (default: the contract's uniform scale, centred); with "pad" what
    lies outside the input is the recipe's background, whatever its ``edges``.
    ``lattice``: animated frames over an input (video, live) interpolate the map
    from a walked lattice where it can be trusted
    (:mod:`marblevideo.opencl.lattice`), unless the recipe says
    ``"lattice": false``; False walks every subsample. Stills always walk every
    subsample. A recipe with ``motion`` turns on its renderer's loop walk: its ops
    change from frame to frame, and one program serves them all (no build per
    stroke; the loop walk's frames equal the unrolled program's).
    """

    def __init__(
        self,
        recipe: RecipeLike,
        renderer: Renderer | None = None,
        device: str | None = None,
        adaptive: bool | None = None,
        fit: str | None = None,
        lattice: bool = True,
    ):
        if fit is not None and fit not in FIT_MODES:
            raise UsageError(f"--fit: expected one of {', '.join(FIT_MODES)}, got {fit!r}")
        self.recipe = as_recipe(recipe)
        self.renderer = renderer or Renderer(device, adaptive=adaptive)
        self.fit = fit
        #: whether animated frames may interpolate from a lattice (option and recipe)
        self.lattice = lattice and self.recipe.lattice
        if self.recipe.motion is not None:
            self.renderer.loop_walk = True
        self._geometry: dict[tuple, Geometry] = {}

    def with_recipe(self, recipe: RecipeLike) -> Marbler:
        """A marbler of ``recipe`` on this one's renderer, with its ``fit`` and
        ``lattice`` (the live session's recipe with motion strokes added)."""
        return type(self)(recipe, renderer=self.renderer, fit=self.fit, lattice=self.lattice)

    def geometry(
        self,
        out_size: tuple[int, int],
        input_size: tuple[int, int] | None,
        view: tuple[float, float, float, float] | None = None,
    ) -> Geometry:
        key = (out_size, input_size, view)
        geom = self._geometry.get(key)
        if geom is None:
            canvas = self.canvas(input_size)
            geom = geometry(canvas, out_size, input_size, view, self.fit)
            self._geometry[key] = geom
        return geom

    def canvas(self, input_size: tuple[int, int] | None) -> tuple[float, float]:
        """The recipe's canvas, else the input's size, else the blank sheet's default."""
        return self.recipe.canvas or input_size or blank_canvas(self.recipe)

    def render(
        self,
        image: np.ndarray | None = None,
        time: float | None = None,
        size: tuple[int, int] | None = None,
        view: tuple[float, float, float, float] | None = None,
        *,
        static: bool = False,
        animated: bool = False,
    ) -> np.ndarray:
        """One marbled frame of ``image`` (or of the blank sheet) at ``time``;
        ``static``: later frames repeat these values (see :class:`Renderer`);
        ``animated``: a frame of a video or live session, which interpolates
        from a lattice when :attr:`lattice` allows and the recipe moves."""
        spec, geom = self.frame_at(image_size(image), time, size, view)
        lattice = animated and frames_route(self.recipe.is_animated, self.lattice).lattice
        return self.renderer.render(spec, geom, image, static=static, lattice=lattice)

    def frame_at(
        self, input_size, time, size, view, recipe: Recipe | None = None
    ) -> tuple[FrameSpec, Geometry]:
        """The recipe's values at ``time`` (default: its end) and the geometry of a
        render at ``size`` of an input of ``input_size`` (w, h), or of the blank
        sheet (None); ``recipe``: the one rendered at this frame in place of
        :attr:`recipe` (a stirred recipe's, with its motion strokes)."""
        recipe = recipe or self.recipe
        t = recipe.end_time() if time is None else float(time)
        if size is None:
            size = input_size or blank_size(recipe)
        spec = recipe.at(t, self.canvas(input_size))
        if self.fit == "pad" and input_size is not None:
            spec = dataclasses.replace(spec, edges="background")
        return spec, self.geometry(size, input_size, view)

    def render_bands(
        self,
        image: np.ndarray | None = None,
        time: float | None = None,
        size: tuple[int, int] | None = None,
        view: tuple[float, float, float, float] | None = None,
        rows: int | None = None,
    ):
        """Iterate the frame of :meth:`render` as bands of ``rows`` rows, top to bottom
        (default :func:`marblevideo.media.tiled.band_rows`; see
        :func:`marblevideo.recipe.geometry.bands`); each band is (n, w, 4) RGBA uint8."""
        from marblevideo.media.tiled import band_rows
        from marblevideo.recipe.geometry import bands

        spec, geom = self.frame_at(image_size(image), time, size, view)
        rows = rows or band_rows(geom.out_w)
        for _, band in bands(lambda g: self.renderer.render(spec, g, image), geom, rows):
            yield band

    def transform(self, size: tuple[int, int] | None = None) -> FrameTransform:
        """(frame, t) -> marbled frame for the video pipeline, with its I420 form."""
        return FrameTransform(self, size)


class FrameTransform(PipelinedTransform):
    """A :class:`Marbler` as the video pipeline's transform of an input's frames, at
    output ``size`` (default: the input's): called as ``(rgba, t) -> rgba``, or
    with one frame in flight on the device, RGBA or I420 (converted on the
    device, or warped plane by plane: see :mod:`marblevideo.jobs.pipeline`), the
    way the job's :class:`~marblevideo.jobs.route.Route` says.

    A recipe with ``motion`` :attr:`watches`: every frame is seen first, in time
    order (:meth:`watch`, by the pipeline; by ``__call__`` itself), by a
    :class:`~marblevideo.motion.StirredRecipe`, and rendered with the recipe it
    returns (the recipe's ops and the motion strokes so far); :attr:`stirred`
    holds the take (None before the first frame)."""

    planar = True

    def __init__(self, marbler: Marbler, size: tuple[int, int] | None = None):
        self.marbler, self.size = marbler, size
        self.watches = marbler.recipe.motion is not None
        self.moves = marbler.recipe.is_animated or self.watches
        self.lattice = marbler.lattice
        #: the route of frames called one by one (``transform(rgba, t)``)
        self.route = frames_route(self.moves, self.lattice, None, self.watches)
        self.stirred: StirredRecipe | None = None
        self._current: Recipe | None = None  # the recipe of the frame watched last

    def __call__(self, frame: np.ndarray, t: float) -> np.ndarray:
        if self.watches:
            self.watch(frame, t)
        return self.start_rgba(frame, t, self.route)()

    def watch(self, frame: np.ndarray, t: float) -> None:
        """See the input's frame at ``t`` (its luma plane, or RGBA; times increasing):
        the next frame started renders the recipe stirred by the motion so far."""
        if self.stirred is None:
            from marblevideo.motion import StirredRecipe  # OpenCV, for inputs that move only

            size = (frame.shape[1], frame.shape[0])
            self.stirred = StirredRecipe(self.marbler.recipe, size, self.marbler.fit, self.size)
        self._current = self.stirred.see(frame, t)

    def start_rgba(self, frame: np.ndarray, t: float, route: Route) -> Callable[[], np.ndarray]:
        """The frame queued on the device: returns a function that waits for the
        frame and returns it. The video pipeline queues the next frame before
        waiting, so the device works while the host prepares that frame."""
        spec, geom = self.marbler.frame_at(image_size(frame), t, self.size, None, self._current)
        return self.marbler.renderer.render(
            spec, geom, frame, static=route.static, wait=False, lattice=route.lattice
        )

    def start_i420(
        self, planes, t: float, src: YuvMatrix, route: Route
    ) -> Callable[[], np.ndarray]:
        """:meth:`start_rgba` for I420 ``planes`` (y, u, v) in ``src``; the frame
        comes back as packed I420 in ``route.i420``."""
        input_size = planes[0].shape[::-1]
        spec, geom = self.marbler.frame_at(input_size, t, self.size, None, self._current)
        return self.marbler.renderer.render_i420(
            spec,
            geom,
            planes,
            src,
            route.i420,
            static=route.static,
            wait=False,
            lattice=route.lattice,
        )


class SheetSource(PipelinedSource):
    """A :class:`Marbler`'s frames at ``size`` over one still ``image`` (RGBA), or
    over the blank sheet when it is None, as the frames of a video: called as
    ``(t) -> rgba``; a blank sheet of even size is :attr:`planar`: its frames are
    rendered and converted to I420 on the device."""

    def __init__(self, marbler: Marbler, size: tuple[int, int], image: np.ndarray | None = None):
        self.marbler, self.size, self.image = marbler, size, image
        self.moves = marbler.recipe.is_animated
        self.planar = image is None and size[0] % 2 == 0 and size[1] % 2 == 0
        #: a recipe that does not move makes one frame, given again
        self.still: np.ndarray | None = None

    def __call__(self, t: float) -> np.ndarray:
        if self.still is not None:
            return self.still
        frame = self.marbler.render(self.image, t, self.size, animated=True)
        if not self.moves:
            self.still = frame
        return frame

    def start_i420(self, t: float, matrix: YuvMatrix) -> Callable[[], np.ndarray]:
        """The frame at ``t`` queued on the device: a function that waits for it and
        returns it as packed I420 in ``matrix``."""
        spec, geom = self.marbler.frame_at(None, t, self.size, None)
        return self.marbler.renderer.render_i420(spec, geom, None, None, matrix, wait=False)
