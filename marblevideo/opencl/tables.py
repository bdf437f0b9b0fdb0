"""Reused maps: over an input, a frame whose values, geometry and sizes equal the
last frame's lands every subsample where it landed before (a static recipe over
a video), so where every subsample lands is recorded once in a table and later
frames only fetch and blend (within one level of a fresh walk; see kernels/tables.cl).

A frame is drawn from the tables when its maps (its *key*: structure, packed
values, geometry, sizes) equal the last frame's, or when the caller promises
that later frames will repeat them (``static``), and when its tables fit in
:data:`TABLE_LIMIT`. An OpenCL error forgets the tables (one being walked may be
half-written), so stale maps are never served.
"""

from __future__ import annotations

import numpy as np

from marblevideo.opencl.kernel_args import set_args
from marblevideo.opencl.program import Built
from marblevideo.opencl.queue import DeviceQueue
from marblevideo.recipe.antialias import pattern

#: Largest table of reused maps (bytes: 8 per subsample per pixel; 1080p RGSS
#: takes 66 MB). Frames needing more are walked afresh every time.
TABLE_LIMIT = 512 << 20


class ReusedMaps:
    """The tables of one renderer: which maps the last frame was walked for, and
    which maps the tables hold. ``lanes``: the programs' vector width (a table's
    rows are padded to it)."""

    def __init__(self, queue: DeviceQueue, lanes: int):
        self.queue, self.lanes = queue, lanes
        #: the largest table accepted (bytes of one buffer of a pair)
        self.limit = min(TABLE_LIMIT, queue.info.device.max_mem_alloc_size)
        self._last: tuple | None = None
        self._held: tuple | None = None

    def decide(self, key: tuple, table_bytes: int, static: bool = False) -> bool:
        """Whether a frame whose maps are ``key`` is drawn from the tables: it lands
        where the last frame's did (or, ``static``, later frames will land where it
        does) and its tables (``table_bytes`` in one buffer of each pair) fit; ``key``
        becomes the last frame's."""
        reuse = (static or key == self._last) and table_bytes <= self.limit
        self._last = key
        return reuse

    def forget_last(self) -> None:
        """No frame came before the next one: it decides as a renderer's first."""
        self._last = None

    def holds(self, key: tuple) -> bool:
        """Whether the tables hold the maps ``key`` (else they are walked first)."""
        return self._held == key

    def hold(self, key: tuple | None) -> None:
        """Record that the tables now hold ``key`` (None: nothing trustworthy)."""
        self._held = key

    def stride(self, w: int) -> int:
        """Row stride of a table of a w-wide output (padded to whole vectors)."""
        return -(-w // self.lanes) * self.lanes

    def nbytes(self, antialias: str, w: int, h: int) -> int:
        """Bytes of each of the two table buffers of a w x h output."""
        return len(pattern(antialias)) * h * self.stride(w) * 4

    def table(self, built: Built, names, w, h, antialias, common, walk: bool) -> tuple:
        """(taps, wts, row stride) of the table of a w x h output in the buffers
        ``names``, walked first by marble_table over ``common`` (the walk's
        arguments by name) when ``walk``."""
        stride = self.stride(w)
        nbytes = self.nbytes(antialias, w, h)
        taps, wts = (self.queue.buffer(name, nbytes) for name in names)
        if walk:
            k = built.kernels["marble_table"]
            size = dict(w=np.int32(w), h=np.int32(h), tstride=np.int32(stride))
            set_args(k, common, taps=taps, wts=wts, **size)
            self.queue.launch(k, -(-w // self.lanes) * -(-h // built.rows))
        return taps, wts, np.int32(stride)

    def render(self, built: Built, dst, w: int, h: int, common: dict, key: tuple) -> None:
        """An RGBA frame fetched and blended from the table, walked first if it
        holds other maps."""
        antialias = key[0].antialias
        walk = not self.holds(key)
        taps, wts, stride = self.table(built, ("taps", "wts"), w, h, antialias, common, walk)
        self.hold(key)
        k = built.kernels["marble_apply"]
        size = dict(w=np.int32(w), h=np.int32(h), tstride=stride)
        set_args(k, common, dst=dst, taps=taps, wts=wts, **size)
        self.queue.launch(k, -(-w // self.lanes) * h)
