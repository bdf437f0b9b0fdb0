"""Walked frames: every subsample walked afresh (:class:`FreshWalk`), or the full
pattern only where a pixel needs it (:class:`AdaptiveWalk`).

Adaptive antialiasing runs three passes (see marble.cl): one walk at every
pixel centre of a grid one pixel larger than the output, a classification of
each pixel's 3x3 neighbourhood (one ink all round: that ink; none: the
background, or over a smooth map the pattern's samples at positions from a
quadratic model of the nine walks), and the full pattern for the pixels left
on a list. The list's length stays on the device: the list kernel strides
through it, so the host never waits in mid-frame.
"""

from __future__ import annotations

import numpy as np

from marblevideo.opencl.program import Built
from marblevideo.opencl.queue import DeviceQueue

#: Work-group size of the classify kernels (their list takes one global atomic per group).
CLASSIFY_GROUP = 64
#: Work-groups of a list kernel per compute unit, and their size: its work-items
#: stride through the list (PoCL runs a work-group on one thread, so there must
#: be several per core for the cores to share the list evenly)
LIST_GROUPS_PER_UNIT, LIST_GROUP = 8, 16


class FreshWalk:
    """Every subsample of every pixel walked (the ``marble`` kernel)."""

    def __init__(self, queue: DeviceQueue, lanes: int):
        self.queue, self.lanes = queue, lanes

    def render(self, built: Built, dst, w: int, h: int, common: tuple) -> None:
        k = built.kernels["marble"]
        k.set_args(dst, np.int32(w), np.int32(h), *common)
        self.queue.launch(k, -(-w // self.lanes) * -(-h // built.rows))


class AdaptiveWalk:
    """The three passes of adaptive antialiasing, for RGBA frames (:meth:`render`)
    and for a plane of a video frame (:meth:`plane`); :attr:`last_full_pixels`:
    the pixels (samples of every plane) the last render gave the full pattern."""

    def __init__(self, queue: DeviceQueue, lanes: int):
        self.queue, self.lanes = queue, lanes
        device = queue.info.device
        self.group = min(CLASSIFY_GROUP, device.max_work_group_size)
        self.list_group = min(LIST_GROUP, device.max_work_group_size)
        self.list_items = device.max_compute_units * LIST_GROUPS_PER_UNIT * self.list_group
        self._counts: list = []  # (host int32, event) of the last render's lists

    @property
    def last_full_pixels(self) -> int | None:
        if not self._counts:
            return None
        for _, event in self._counts:
            event.wait()
        return sum(int(count[0]) for count, _ in self._counts)

    def forget(self) -> None:
        """The next render is not adaptive (until one is)."""
        self._counts = []

    def _centres(self, built: Built, w: int, h: int, pbuf, maps, lbuf, has_input: bool):
        """Walk the grid of centres: (inkmap, sxmap, symap, gstride)."""
        queue, lanes = self.queue, self.lanes
        gstride, gh = -(-w // lanes) * lanes + 2 * lanes, h + 2
        cells = gstride * gh
        inkmap = queue.buffer("inkmap", cells * 4)
        size = cells * 4 if has_input else 4  # end points: only over an input
        sxmap, symap = queue.buffer("sxmap", size), queue.buffer("symap", size)
        k = built.kernels["marble_centres"]
        k.set_args(inkmap, sxmap, symap, np.int32(gstride), np.int32(gh), pbuf, *maps, lbuf)
        queue.launch(k, gstride // lanes * -(-gh // built.chains))
        return inkmap, sxmap, symap, np.int32(gstride)

    def _list(self, w: int, h: int, name: str):
        """The list buffer and its counter ``name``, cleared on the device."""
        queue = self.queue
        counter = queue.buffer(name, 4)
        queue.fill_zero(counter, 4)
        return queue.buffer("list", w * h * 4), counter

    def _read_count(self, counter) -> None:
        count = np.zeros(1, np.int32)
        self._counts.append((count, self.queue.read_later(count, counter)))

    def render(self, built: Built, dst, w, h, common, pbuf, maps, has_input: bool) -> None:
        """An RGBA frame; ``maps``: the geometry's two float4 kernel arguments;
        ``pbuf``: the params; ``common``: the walk's arguments (KPARAMS)."""
        self._counts = []
        grid = self._centres(built, w, h, pbuf, maps, common[-1], has_input)
        listing, counter = self._list(w, h, "count")
        k = built.kernels["marble_classify"]
        k.set_args(dst, np.int32(w), np.int32(h), *grid, listing, counter, *common)
        self.queue.launch(k, -(-w // self.lanes) * h, self.group)
        k = built.kernels["marble_list"]
        k.set_args(dst, np.int32(w), listing, counter, *common)
        self.queue.launch(k, self.list_items, self.list_group)
        self._read_count(counter)

    def plane(self, built: Built, head: tuple, w: int, h: int, common, maps, first: bool) -> None:
        """A plane of a video frame: ``head`` are marble_plane's arguments before
        KPARAMS, ``common`` KPARAMS; ``first``: the frame's first plane."""
        if first:
            self._counts = []
        pbuf, lbuf = common[3], common[-1]
        grid = self._centres(built, w, h, pbuf, maps, lbuf, True)
        listing, counter = self._list(w, h, "count")
        k = built.kernels["marble_plane_classify"]
        k.set_args(*head, *grid, listing, counter, *common)
        self.queue.launch(k, -(-w // self.lanes) * h, self.group)
        k = built.kernels["marble_plane_list"]
        dst, off0, off1, _, _, q1, chroma = head
        k.set_args(dst, off0, off1, np.int32(w), q1, chroma, listing, counter, *common)
        self.queue.launch(k, self.list_items, self.list_group)
        self._read_count(counter)
