"""The transform stage of a video render (:mod:`marblevideo.jobs.pipeline`): what
a transform may offer besides ``transform(rgba, t) -> rgba`` (the protocols
below, probed once per job), and the adapters that call it on one decoded item
in place, checking what it returns.

I420 frames are packed or as planes (:func:`marblevideo.media.yuv.split_i420`);
an RGBA frame is a C-contiguous ``(h, w, 4)`` uint8 array. A ``*_start`` method
returns the function that finishes its frame, called once the next frame has
been started (one frame in flight).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, runtime_checkable

import numpy as np

from marblevideo.media.video import VideoItem, VideoOptions
from marblevideo.media.yuv import YuvMatrix, split_i420
from marblevideo.recipe.frame import stretch_note


@runtime_checkable
class PlanarTransform(Protocol):
    """A transform that takes and gives 8-bit 4:2:0 frames (see the module)."""

    def i420(self, planes, t: float, src: YuvMatrix, dst: YuvMatrix): ...


@runtime_checkable
class PlanarStart(Protocol):
    """:class:`PlanarTransform` with one frame in flight: returns a function that
    finishes the frame."""

    def i420_start(self, planes, t: float, src: YuvMatrix, dst: YuvMatrix) -> Callable: ...


@runtime_checkable
class RgbaStart(Protocol):
    """A transform with one RGBA frame in flight: returns a function that finishes it."""

    def rgba_start(self, rgba: np.ndarray, t: float) -> Callable[[], np.ndarray]: ...


@runtime_checkable
class PlanarSource(Protocol):
    """Frames of a blank sheet (:func:`~marblevideo.jobs.pipeline.render_sheet`)
    that can come as I420."""

    def i420(self, t: float, matrix: YuvMatrix) -> np.ndarray | None: ...


@runtime_checkable
class PlanarSourceStart(Protocol):
    """:class:`PlanarSource` with one frame in flight."""

    def i420_start(self, t: float, matrix: YuvMatrix) -> Callable | None: ...


def check_i420(planes):
    try:
        split_i420(planes)
    except ValueError as exc:
        raise ValueError(f"transform.i420 returned no I420 frame: {exc}") from None
    return planes


def _started(finish, kind: str) -> Callable[[], object]:
    if not callable(finish):
        raise TypeError(f"transform.{kind}_start must return a function")
    return finish


def check_frame(rgba) -> np.ndarray:
    if not isinstance(rgba, np.ndarray) or rgba.dtype != np.uint8 or rgba.ndim != 3:
        raise TypeError("transform must return an (h, w, 4) uint8 numpy array")
    if rgba.shape[2] != 4:
        raise ValueError(f"transform must return 4 channels (RGBA), got shape {rgba.shape}")
    return np.ascontiguousarray(rgba)


class TransformStage:
    """The transform stage of :func:`~marblevideo.jobs.pipeline.transcode`: one
    decoded item marbled in place, as I420 planes where the transform and output
    allow (:attr:`planar`), else as RGBA; returns the function that finishes a
    frame in flight, or None."""

    def __init__(self, transform, out_matrix: YuvMatrix | None, options: VideoOptions, notify):
        self.transform, self.out_matrix, self.options, self.notify = (
            transform,
            out_matrix,
            options,
            notify,
        )
        planar = isinstance(transform, PlanarTransform) and out_matrix is not None
        self.planar = planar
        self.i420 = transform.i420 if planar else None
        self.i420_start = (
            transform.i420_start if planar and isinstance(transform, PlanarStart) else None
        )
        self.rgba_start = transform.rgba_start if isinstance(transform, RgbaStart) else None
        self.first = True

    def __call__(self, item: VideoItem) -> Callable[[], None] | None:
        options = self.options
        if self.first and options.size is not None and options.fit is None:
            note = stretch_note(item.shape[::-1], tuple(options.size))
            if note:
                self.notify(note)
        self.first = False
        if item.i420 is not None:
            args = (item.i420, item.t, item.matrix, self.out_matrix)
            if self.i420_start is None:
                item.i420 = check_i420(self.i420(*args))
                return None
            started = _started(self.i420_start(*args), "i420")
            return lambda: setattr(item, "i420", check_i420(started()))
        if self.rgba_start is None:
            item.rgba = check_frame(self.transform(item.rgba, item.t))
            return None
        started = _started(self.rgba_start(item.rgba, item.t), "rgba")
        return lambda: setattr(item, "rgba", check_frame(started()))


class SheetStage:
    """The transform stage of :func:`~marblevideo.jobs.pipeline.render_sheet`: each
    item's frame rendered at its time, as I420 (BT.601, limited range) where the
    source and output allow."""

    MATRIX = YuvMatrix.of(None, None)

    def __init__(self, render_at, i420: bool):
        self.render_at = render_at
        self.planar = render_at.i420 if i420 and isinstance(render_at, PlanarSource) else None
        self.start = None
        if self.planar is not None and isinstance(render_at, PlanarSourceStart):
            self.start = render_at.i420_start

    def __call__(self, item: VideoItem) -> Callable[[], None] | None:
        if self.start is not None:
            started = self.start(item.t, self.MATRIX)
            if started is not None:
                started = _started(started, "i420")
                return lambda: setattr(item, "i420", check_i420(started()))
        planes = None
        if self.planar is not None and self.start is None:
            planes = self.planar(item.t, self.MATRIX)
        if planes is not None:
            item.i420 = check_i420(planes)
        else:
            item.rgba = check_frame(self.render_at(item.t))
        return None
