"""A job's route: how every one of its frames goes, decided once from the input,
the output's plan and the recipe, and handed to the reader (which frames come as
I420), the transform stage (which way it calls the transform) and the renderer
(:meth:`marblevideo.opencl.renderer.Renderer.render` and ``render_i420``'s
``static`` and ``lattice``, from which its one strategy chooser starts)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from marblevideo.media.yuv import YuvMatrix

if TYPE_CHECKING:
    from marblevideo.media.encode import OutputPlan

#: The colours of a blank sheet's I420 frames: untagged, so BT.601, limited range.
SHEET_MATRIX = YuvMatrix.of(None, None)


@dataclass(frozen=True)
class Route:
    """``i420``: frames travel as I420 planes and the result is I420 in this matrix
    (the input's own, or :data:`SHEET_MATRIX`); None: as RGBA. ``lattice``: animated
    frames over an input interpolate the map from a walked lattice where it can be
    trusted; False walks every subsample. ``static``: every frame repeats the first
    one's values, so its maps are walked once and kept (the tables of reused maps).
    ``luma``: the transform sees each frame's luma before marbling it (a recipe's
    ``motion``), so the reader hands over the frame's decoded luma plane, the same
    whether its pixels travel as I420 or RGBA."""

    i420: YuvMatrix | None = None
    lattice: bool = False
    static: bool = False
    luma: bool = False

    @property
    def planar(self) -> bool:
        """Whether frames travel as I420."""
        return self.i420 is not None


def frames_route(
    moves: bool, lattice: bool, i420: YuvMatrix | None = None, luma: bool = False
) -> Route:
    """The route of an input's frames for a recipe that ``moves`` (or not) and allows
    the ``lattice``: a lattice only for frames that move; tables for those that do not;
    ``luma``: the transform sees each frame's luma."""
    return Route(i420, lattice and moves, not moves, luma)


def video_route(transform, colors: dict, plan: OutputPlan, size) -> Route:
    """The route of an input's frames through ``transform`` (a
    :class:`~marblevideo.jobs.transforms.PipelinedTransform`: whether it is
    ``planar``, its recipe ``moves``, it allows the ``lattice``, it ``watches`` each
    frame's luma): I420 in the input's
    tags (``colors``) where the output is yuv420p of an even ``size`` (None: the
    input's; odd inputs go as RGBA frame by frame)."""
    matrix = None
    even = not (size and any(v % 2 for v in size))
    if transform.planar and plan.pix_fmt == "yuv420p" and even:
        matrix = YuvMatrix.of(colors["colorspace"], colors["color_range"])
    return frames_route(transform.moves, transform.lattice, matrix, transform.watches)


def sheet_route(planar: bool, moves: bool, plan: OutputPlan) -> Route:
    """The route of a sheet's frames (a blank sheet's or a still's): I420 in
    :data:`SHEET_MATRIX` where the source can make it (``planar``) and the output is
    yuv420p; never a lattice (a blank sheet has no input to interpolate over)."""
    planar = planar and plan.pix_fmt == "yuv420p"
    return Route(SHEET_MATRIX if planar else None, False, not moves)
