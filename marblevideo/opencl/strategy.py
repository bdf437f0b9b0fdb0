"""The one place a frame's rendering strategy is chosen, for RGBA and planar (I420)
frames alike: from the tables of reused maps, interpolated from a walked lattice,
adaptively sampled, or walked afresh (the classes of
:mod:`~marblevideo.opencl.tables`, :mod:`~marblevideo.opencl.lattice` and
:mod:`~marblevideo.opencl.walks`)."""

from __future__ import annotations

from marblevideo.recipe.antialias import pattern
from marblevideo.recipe.frame import FrameSpec

STRATEGIES = ("tables", "lattice", "adaptive", "fresh")


class Strategies:
    """The strategy chooser of ``renderer`` (a
    :class:`~marblevideo.opencl.renderer.Renderer`: its ``reuse_maps``,
    ``adaptive``, ``tables``, ``lattice_walk`` and ``adaptive_walk``, read at each
    choice)."""

    def __init__(self, renderer):
        self.renderer = renderer

    def choose(
        self, key, nbytes: int, packed, *, static: bool, lattice: bool, adaptive=None
    ) -> str:
        """One of :data:`STRATEGIES`: "tables", from the tables of reused maps (over
        an input whose ``key``, the values, geometry and sizes, equals the previous
        frame's, or ``static``; ``nbytes``: the tables' size); "lattice",
        interpolated from a walked lattice (asked for, and worth it for these
        ``packed`` parameters); "adaptive", the full pattern only where a pixel
        needs it (``adaptive()`` says whether); else "fresh", every subsample
        walked. ``key`` None: a blank sheet, which has no tables and no lattice."""
        r = self.renderer
        has_input = key is not None
        if has_input and r.reuse_maps and r.tables.decide(key, nbytes, static):
            return "tables"
        if lattice and has_input and r.lattice_walk.worth(packed):
            return "lattice"
        if adaptive is not None and adaptive():
            return "adaptive"
        return "fresh"

    def adaptive(self, spec: FrameSpec, has_input: bool, w: int, h: int, structure) -> bool:
        """Whether an RGBA frame is sampled adaptively: only with more than one
        subsample; the renderer's ``adaptive`` where it is given, else on blank
        sheets where it pays (``adaptive_walk.worth``)."""
        r = self.renderer
        if len(pattern(spec.antialias)) < 2:
            return False
        if r.adaptive is not None:
            return r.adaptive
        return not has_input and r.adaptive_walk.worth(w, h, structure)
