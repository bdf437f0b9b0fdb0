"""Walked frames: every subsample walked afresh (:class:`FreshWalk`), or the full
pattern only where a pixel needs it (:class:`AdaptiveWalk`).

Adaptive antialiasing runs three passes (see kernels/adaptive.cl): one walk at every
pixel centre of a grid one pixel larger than the output, a classification of
each pixel's 3x3 neighbourhood (one ink all round: that ink; none: the
background, or over a smooth map the pattern's samples interpolated from the
nine walks), and the full pattern for the pixels left on a list.
"""

from __future__ import annotations

import numpy as np

from marblevideo.opencl.kernel_args import set_args
from marblevideo.opencl.program import Built
from marblevideo.opencl.queue import DeviceQueue

#: Work-group size of marble_classify (its list takes one global atomic per group).
CLASSIFY_GROUP = 64
#: Above this share of pixels on the list, the three passes cost more than the
#: full pattern everywhere (measured on the samples: a share of 0.6 took 0.92x
#: the full pattern's time, 0.8 took 1.13x; BENCHMARKS.md, session 12).
BUSY_SHARE = 0.7
#: After a busy frame, frames of its size and program take the full pattern, and
#: every PROBE_EVERY-th is adaptive again, to see whether the design is still busy.
PROBE_EVERY = 8


class FreshWalk:
    """Every subsample of every pixel walked (the ``marble`` kernel)."""

    def __init__(self, queue: DeviceQueue, lanes: int):
        self.queue, self.lanes = queue, lanes

    def render(self, built: Built, dst, w: int, h: int, common: dict) -> None:
        """``common``: the walk's arguments by name (see kernel_args.walk_args)."""
        k = built.kernels["marble"]
        set_args(k, common, dst=dst, w=np.int32(w), h=np.int32(h))
        self.queue.launch(k, -(-w // self.lanes) * -(-h // built.rows))


class AdaptiveWalk:
    """The three passes of adaptive antialiasing; :attr:`last_full_pixels`: the
    pixels the last render gave the full pattern. :meth:`worth` says whether
    the next frame of a size should take them (see BUSY_SHARE)."""

    def __init__(self, queue: DeviceQueue, lanes: int):
        self.queue, self.lanes = queue, lanes
        self.group = min(CLASSIFY_GROUP, queue.info.device.max_work_group_size)
        self.last_full_pixels: int | None = None
        self._busy = None  # (w, h, program) of the last busy frame
        self._full_since = 0  # frames like it given the full pattern since
        self._asked = None

    def worth(self, w: int, h: int, program) -> bool:
        """Whether a frame of ``w`` x ``h`` drawn by ``program`` (a hashable key)
        should be sampled adaptively: not after a busy frame of the same size and
        program, except every PROBE_EVERY-th frame."""
        self._asked = (w, h, program)
        if self._busy != self._asked:
            return True
        self._full_since += 1
        return self._full_since >= PROBE_EVERY

    def forget(self) -> None:
        """A new job: no frame came before."""
        self._busy = None

    def render(self, built: Built, dst, w, h, common, pbuf, maps, has_input: bool) -> None:
        """``common``: the walk's arguments by name; ``maps``: the geometry's two
        float4 kernel arguments; ``pbuf``: the params."""
        queue, lanes = self.queue, self.lanes
        nbx = -(-w // lanes)
        gstride, gh = nbx * lanes + 2 * lanes, h + 2
        cells = gstride * gh
        inkmap = queue.buffer("inkmap", cells * 4)
        size = cells * 4 if has_input else 4  # end points: only over an input
        sxmap, symap = queue.buffer("sxmap", size), queue.buffer("symap", size)
        listing = queue.buffer("list", w * h * 4)
        counter = queue.buffer("count", 4)
        zero = np.zeros(1, np.int32)
        cleared = queue.upload(counter, zero)
        centres = built.kernels["marble_centres"]
        grid = dict(inkmap=inkmap, sxmap=sxmap, symap=symap, gstride=np.int32(gstride))
        gc, gi = maps
        set_args(centres, common, **grid, gh=np.int32(gh), params=pbuf, gc=gc, gi=gi)
        queue.launch(centres, gstride // lanes * -(-gh // built.chains))
        classify = built.kernels["marble_classify"]
        size = dict(dst=dst, w=np.int32(w), h=np.int32(h))
        set_args(classify, common, **size, **grid, list=listing, count=counter)
        queue.launch(classify, nbx * h, self.group)
        n = queue.count(counter)
        del cleared  # copied before the count was read
        self.last_full_pixels = n
        self._busy = self._asked if n > BUSY_SHARE * w * h else None
        self._full_since = 0
        if n:
            full = built.kernels["marble_list"]
            set_args(full, common, dst=dst, w=np.int32(w), list=listing, count=np.int32(n))
            queue.launch(full, -(-n // (lanes * built.rows)))
