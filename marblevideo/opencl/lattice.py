"""The interpolated inverse map of animated frames (kernels/lattice.cl).

An animated frame over an input walks its exact map only on a lattice: a fine
lattice every H = S / 2 luma output pixels (S: :attr:`LatticeWalk.spacing`),
whose points' walks decide for each S x S cell whether it is all one ink, smooth
enough that every subsample's end point is interpolated bilinearly between the
four fine points round its pixel (luma and chroma from the same lattice), or
walked exactly (see :data:`RULES`). Conventions: output pixel (i, j) of the
luma plane covers [i, i + 1] x [j, j + 1]; fine point (i, j) lies at (i H, j H);
tolerances are in input (luma) pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from marblevideo.opencl.kernel_args import set_args
from marblevideo.opencl.program import Built, Packed
from marblevideo.opencl.queue import DeviceQueue, float4
from marblevideo.ops import PSTRIDE
from marblevideo.recipe.frame import Geometry

#: Output pixels per cell side of the coarse lattice (even; every other fine point).
SPACING = 8
#: The largest distance (input pixels) between a walked point of a cell (edge
#: midpoints, centre) and the bilinear interpolation of its corners.
TOLERANCE = 1.0 / 16.0
#: The largest step between the ends of neighbouring fine points, against the
#: step between the points themselves (canvas units both), that the lattice
#: follows: a cell that the walk squeezes more (where ink is drawn into
#: filaments) is walked.
REACH = 4.0
#: The rules that put a cell on the exact walk (bits of marble_lattice_cells'
#: ``rules``): its nine points on different inks (or some on ink), an edge
#: midpoint or the centre off the interpolation by more than TOLERANCE, a step
#: longer than REACH. Tests switch them off one by one to see them matter.
RULE_INK, RULE_CENTRE, RULE_REACH = 1, 2, 4
RULES = RULE_INK | RULE_CENTRE | RULE_REACH
#: The state of a cell walked exactly (lattice.cl's WALK_CELL).
WALK_CELL = -2
#: Fewer ops walked this frame (not still) than this, and the frame is walked
#: exactly: interpolating a subsample costs about what walking one cheap op
#: does (720p I420, best of 31: one keyed turn 8.2 ms walked, 11.3
#: interpolated; three smooth ops 13.4 and 11.9; BENCHMARKS.md, session 13).
MIN_WALKED_OPS = 3
#: On a GPU the lattice is off by default (min_ops infinite): an H100 walks a
#: 720p I420 frame of the 12-op recipe, RGSS, in 0.6-0.9 ms and interpolates
#: it in 0.8-1.1 (BENCHMARKS.md, session 14); it pays only where the walk is
#: the work, on CPUs.
GPU_MIN_WALKED_OPS = math.inf


@dataclass(frozen=True)
class Lattice:
    """A frame's walked lattice: the shading kernels' ``LATTICE_ARGS`` by name
    (:mod:`~marblevideo.opencl.kernel_args`: cell states, fine points' end
    points in canvas units, the fine lattice's row stride, the coarse lattice's
    size, canvas -> fine lattice units), and the number of cells."""

    args: dict
    cells: int


class LatticeWalk:
    """Walks a frame's lattice on ``queue`` and shades RGBA frames or I420 planes
    from it. :attr:`spacing`, :attr:`tolerance`, :attr:`reach` and :attr:`rules`
    may be changed between frames (no rebuild)."""

    def __init__(self, queue: DeviceQueue, lanes: int, gpu: bool = False):
        self.queue, self.lanes = queue, lanes
        self.spacing, self.tolerance, self.reach, self.rules = SPACING, TOLERANCE, REACH, RULES
        #: frames walking fewer ops are walked exactly (GPU_MIN_WALKED_OPS on a GPU)
        self.min_ops = GPU_MIN_WALKED_OPS if gpu else MIN_WALKED_OPS
        #: frames drawn from a lattice so far
        self.frames = 0
        self._last: Lattice | None = None

    def worth(self, packed: Packed) -> bool:
        """Whether a frame of these packed values walks enough ops (min_ops) for
        the lattice to pay."""
        codes = packed.params[PSTRIDE - 1 :: PSTRIDE]
        return int(np.count_nonzero(codes >= 0)) >= self.min_ops

    def walk(self, built: Built, geom: Geometry, pbuf, lbuf) -> Lattice:
        """Walk the lattice of a frame of luma geometry ``geom`` over the params
        ``pbuf`` and lists ``lbuf``, and classify its cells."""
        queue, lanes, s = self.queue, self.lanes, self.spacing
        if s < 2 or s % 2:
            raise ValueError(f"lattice spacing must be even and at least 2, got {s}")
        ncx, ncy = -(-geom.out_w // s), -(-geom.out_h // s)
        gw, gh = 2 * ncx + 1, 2 * ncy + 1
        gstride = -(-gw // lanes) * lanes
        ink = queue.buffer("lattice_ink", gstride * gh * 4)
        lx = queue.buffer("lattice_x", gstride * gh * 4)
        ly = queue.buffer("lattice_y", gstride * gh * 4)
        kx, ky, tx, ty = geom.to_canvas
        half = s / 2.0
        # marble_centres walks grid point (i, j) at output (i - 1/2, j - 1/2) through
        # its gc: scaled by H and shifted half a step, point (i, j) is at (i H, j H);
        # gi = identity keeps the end points in canvas units
        gc = float4([kx * half, ky * half, tx + 0.5 * half * kx, ty + 0.5 * half * ky])
        centres = built.kernels["marble_centres"]
        grid = dict(inkmap=ink, sxmap=lx, symap=ly, gstride=np.int32(gstride))
        gi = float4([1, 1, 0, 0])
        set_args(centres, **grid, gh=np.int32(gh), params=pbuf, gc=gc, gi=gi, lists=lbuf)
        queue.launch(centres, gstride // lanes * -(-gh // built.chains))
        state = queue.buffer("lattice_state", ncx * ncy * 4)
        cells = built.kernels["marble_lattice_cells"]
        gi = float4([geom.to_input[0], geom.to_input[1], 0.0, 0.0])
        reach = self.reach * half * max(abs(kx), abs(ky))
        size = dict(ncx=np.int32(ncx), ncy=np.int32(ncy))
        limits = dict(tol=np.float32(self.tolerance), reach=np.float32(reach))
        set_args(cells, **grid, state=state, **size, gi=gi, **limits, rules=np.int32(self.rules))
        queue.launch(cells, ncx * ncy)
        lat = float4([1.0 / (half * kx), 1.0 / (half * ky), tx, ty])
        args = dict(state=state, lx=lx, ly=ly, lstride=np.int32(gstride), **size, lat=lat)
        self._last = Lattice(args, ncx * ncy)
        self.frames += 1
        return self._last

    def render(self, built: Built, dst, w: int, h: int, lattice: Lattice, common: dict) -> None:
        """An RGBA frame (marble's arguments ``common``) shaded from ``lattice``."""
        k = built.kernels["marble_lattice"]
        set_args(k, common, dst=dst, w=np.int32(w), h=np.int32(h), **lattice.args)
        self.queue.launch(k, -(-w // self.lanes) * -(-h // built.rows))

    def render_plane(self, built: Built, head: dict, lattice: Lattice, common: dict) -> None:
        """A plane (marble_plane's arguments ``head`` and ``common``, by name) from ``lattice``."""
        pw, ph = int(head["w"]), int(head["h"])
        k = built.kernels["marble_lattice_plane"]
        set_args(k, common, **head, **lattice.args)
        self.queue.launch(k, -(-pw // self.lanes) * -(-ph // built.rows))

    def refined_share(self) -> float | None:
        """The share of the last lattice's cells walked exactly (waits for the
        queue; for benchmarks and tests), or None before any."""
        if self._last is None:
            return None
        states = self.queue.read(np.empty(self._last.cells, np.int32), self._last.args["state"])
        return float(np.mean(states == WALK_CELL))
