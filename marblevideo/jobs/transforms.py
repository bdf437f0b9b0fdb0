"""The transform stage of a video render (:mod:`marblevideo.jobs.pipeline`): what it
calls (a :class:`PipelinedTransform` of an input's frames, a :class:`PipelinedSource`
of a sheet's), and the stages that call it on one decoded item in place, the way
the job's :class:`~marblevideo.jobs.route.Route` says.

I420 frames travel as planes ``(y, u, v)`` (:mod:`marblevideo.media.yuv`; views of
the decoded frame's buffers: read them, do not keep them) and come back packed;
an RGBA frame is a C-contiguous ``(h, w, 4)`` uint8 array. A ``start_*`` method
returns the function that finishes its frame, called once the next frame has been
started (one frame in flight): the planes stay the pipeline's until then.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from marblevideo.jobs.route import Route
from marblevideo.media.video import VideoItem
from marblevideo.media.yuv import YuvMatrix
from marblevideo.recipe.frame import stretch_note

Finish = Callable[[], np.ndarray]


class PipelinedTransform:
    """A transform of an input's frames with one frame in flight. ``planar``: it
    takes I420 frames too; ``moves``: the recipe is animated; ``lattice``: it may
    interpolate animated frames from a lattice (what :func:`~marblevideo.jobs.route.video_route`
    decides the route from); ``watches``: it sees every frame's luma first
    (:meth:`watch`, a recipe's ``motion``). A plain function ``(rgba, t) -> rgba`` is
    one through :func:`pipelined`."""

    planar = False
    moves = True
    lattice = False
    watches = False

    def watch(self, frame: np.ndarray, t: float) -> None:
        """See the input's frame at ``t`` before it is started, in time order: its
        decoded luma plane (H, W) uint8 where it has one, else the RGBA frame."""

    def start_rgba(self, rgba: np.ndarray, t: float, route: Route) -> Finish:
        """Start the frame ``rgba`` at ``t``: the function that returns it marbled."""
        raise NotImplementedError

    def start_i420(self, planes, t: float, src: YuvMatrix, route: Route) -> Finish:
        """Start the I420 ``planes`` (colours in ``src``) at ``t``: the function that
        returns the frame as packed I420 in ``route.i420``."""
        raise NotImplementedError


class _Function(PipelinedTransform):
    """A plain ``(rgba, t) -> rgba`` function, run as its frame starts."""

    def __init__(self, function: Callable[[np.ndarray, float], np.ndarray]):
        self.function = function

    def start_rgba(self, rgba: np.ndarray, t: float, route: Route) -> Finish:
        result = self.function(rgba, t)
        return lambda: result


def pipelined(transform) -> PipelinedTransform:
    """``transform`` as a :class:`PipelinedTransform` (a plain function wrapped)."""
    return transform if isinstance(transform, PipelinedTransform) else _Function(transform)


class PipelinedSource:
    """The frames of a sheet (a blank sheet's or a still's), called as ``(t) -> rgba``;
    ``planar``: :meth:`start_i420` makes them as I420; ``moves``: the recipe is
    animated. A plain function ``(t) -> rgba`` is one through :func:`sheet_source`."""

    planar = False
    moves = True

    def __call__(self, t: float) -> np.ndarray:
        raise NotImplementedError

    def start_i420(self, t: float, matrix: YuvMatrix) -> Finish:
        """Start the frame at ``t``: the function that returns it as packed I420 in
        ``matrix``."""
        raise NotImplementedError


class _SheetFunction(PipelinedSource):
    def __init__(self, function: Callable[[float], np.ndarray]):
        self.function = function

    def __call__(self, t: float) -> np.ndarray:
        return self.function(t)


def sheet_source(render_at) -> PipelinedSource:
    """``render_at`` as a :class:`PipelinedSource` (a plain function wrapped)."""
    return render_at if isinstance(render_at, PipelinedSource) else _SheetFunction(render_at)


def check_frame(rgba) -> np.ndarray:
    if not isinstance(rgba, np.ndarray) or rgba.dtype != np.uint8 or rgba.ndim != 3:
        raise TypeError("transform must return an (h, w, 4) uint8 numpy array")
    if rgba.shape[2] != 4:
        raise ValueError(f"transform must return 4 channels (RGBA), got shape {rgba.shape}")
    return np.ascontiguousarray(rgba)


def _finished(finish, kind: str) -> Finish:
    if not callable(finish):
        raise TypeError(f"transform.start_{kind} must return a function")
    return finish


class TransformStage:
    """The transform stage of :func:`~marblevideo.jobs.pipeline.transcode`: one
    decoded item marbled in place, as I420 planes where the reader gave them (the
    route's choice), else as RGBA; returns the function that finishes the frame.
    ``size`` and ``fit`` (the options') say whether an input is stretched, which
    the first frame notes through ``notify``."""

    def __init__(self, transform: PipelinedTransform, route: Route, size, fit, notify):
        self.transform, self.route = transform, route
        self.size, self.fit, self.notify = size, fit, notify
        self.first = True

    def __call__(self, item: VideoItem) -> Callable[[], None]:
        if self.first and self.size is not None and self.fit is None:
            note = stretch_note(item.shape[::-1], tuple(self.size))
            if note:
                self.notify(note)
        self.first = False
        if self.transform.watches:
            self.transform.watch(item.luma if item.luma is not None else item.rgba, item.t)
        if item.i420 is not None:
            started = self.transform.start_i420(item.i420, item.t, item.matrix, self.route)
            started = _finished(started, "i420")
            return lambda: setattr(item, "i420", started())
        started = _finished(self.transform.start_rgba(item.rgba, item.t, self.route), "rgba")
        return lambda: setattr(item, "rgba", check_frame(started()))


class SheetStage:
    """The transform stage of :func:`~marblevideo.jobs.pipeline.render_sheet`: each
    item's frame made at its time by ``source``, as I420 in the route's matrix where
    the route says so, else as RGBA."""

    def __init__(self, source: PipelinedSource, route: Route):
        self.source, self.route = source, route

    def __call__(self, item: VideoItem) -> Callable[[], None] | None:
        if self.route.planar:
            started = _finished(self.source.start_i420(item.t, self.route.i420), "i420")
            return lambda: setattr(item, "i420", started())
        item.rgba = check_frame(self.source(item.t))
        return None
