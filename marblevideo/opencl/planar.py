"""Planar video frames: an I420 frame warped plane by plane, in its own colour
matrix throughout (:func:`marblevideo.reference.yuv.render_planes` is the
reference): luma at full resolution, both chroma planes at half, each sampled
through its *quads* (a whole bilinear footprint in one 32-bit gather; see
kernels/planar.cl), with the same tables of reused maps per plane as RGBA frames."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from marblevideo.media.yuv import YuvMatrix
from marblevideo.opencl.kernel_args import set_args, walk_args
from marblevideo.opencl.lattice import LatticeWalk
from marblevideo.opencl.program import Programs, Structure, pack_params
from marblevideo.opencl.queue import DeviceQueue, float4, geometry_args
from marblevideo.opencl.tables import ReusedMaps
from marblevideo.recipe.frame import FrameSpec, Geometry
from marblevideo.recipe.geometry import chroma_geometry, coded_spec


def plane_head(dst, offsets, geom: Geometry, quads, chroma: int) -> dict:
    """The plane kernels' ``PLANE_HEAD`` arguments by name: the output buffer, the
    plane's ``offsets`` in it, its size, its input ``quads`` (q0, q1) and whether
    it is ``chroma``."""
    off0, off1 = map(np.int32, offsets)
    w, h = np.int32(geom.out_w), np.int32(geom.out_h)
    q0, q1 = quads
    return dict(dst=dst, off0=off0, off1=off1, w=w, h=h, q0=q0, q1=q1, chroma=np.int32(chroma))


class PlanarFrames:
    """Renders I420 frames plane by plane on ``queue`` with ``programs``, from the
    ``tables`` of reused maps, a walked ``lattice`` (one for the three planes) or
    a fresh walk, as the renderer's strategy chooser says."""

    def __init__(
        self,
        queue: DeviceQueue,
        programs: Programs,
        tables: ReusedMaps,
        lattice: LatticeWalk,
    ):
        self.queue, self.programs, self.tables = queue, programs, tables
        self.lattice = lattice

    def render(
        self,
        spec: FrameSpec,
        geom: Geometry,
        planes: tuple[np.ndarray, np.ndarray, np.ndarray],
        matrix: YuvMatrix,
        out: np.ndarray | None,
        wait: bool,
        errors: Callable,
        choose: Callable[..., str],
    ):
        """(frame or finishing function, reused): see Renderer.render_i420;
        ``errors`` turns OpenCL errors into DeviceError; ``choose(key, nbytes,
        packed)``: the strategy (Renderer.strategy: "tables", "lattice" or
        "fresh")."""
        queue = self.queue
        w, h = geom.out_w, geom.out_h
        sh, sw = planes[0].shape
        coded = coded_spec(spec, matrix)
        structure = Structure.of(coded, True)
        built = self.programs.get(structure)
        packed = pack_params(coded)
        luma, chroma = geom, chroma_geometry(geom)
        (luma_maps, geo), (chroma_maps, _) = geometry_args(luma), geometry_args(chroma)
        key = ("planes", structure, packed.key, geo.tobytes(), w, h, sw, sh)
        nbytes = sum(self.tables.nbytes(spec.antialias, g.out_w, g.out_h) for g in (luma, chroma))
        drawn = choose(key, nbytes, packed)
        reuse = drawn == "tables"
        result = np.empty((h * 3 // 2, w), np.uint8) if out is None else out
        with errors():
            # the uploads' events hold their host arrays until the copies are done
            uploads: list = []
            pbuf, lbuf = queue.put_params(packed, uploads)
            staged = queue.put_i420(planes, uploads)
            dst = queue.buffer("i420_out", result.nbytes)
            samples = queue.samples(spec.antialias)
            bg = coded.background
            bgc = float4([*bg, 255.0])
            quads = self.quads(built, staged, sw, sh, bg)
            # luma, then both chroma planes at the same points: (geometry, its maps,
            # output offsets, input plane size, quads, chroma flag, table names)
            cw, ch = sw // 2, sh // 2
            luma_job = (luma, luma_maps, (0, 0), (sw, sh), quads[0], quads[0], 0, ("taps", "wts"))
            chroma_offsets = (w * h, w * h * 5 // 4)
            chroma_job = (chroma, chroma_maps, chroma_offsets, (cw, ch), *quads[1:], 1)
            chroma_job += (("ctaps", "cwts"),)
            walk = reuse and not self.tables.holds(key)
            walked = self.lattice.walk(built, luma, pbuf, lbuf) if drawn == "lattice" else None
            for g, maps, offsets, in_size, q0, q1, is_chroma, names in (luma_job, chroma_job):
                head = plane_head(dst, offsets, g, (q0, q1), is_chroma)
                common = walk_args(q0, *map(np.int32, in_size), pbuf, samples, maps, bgc, lbuf)
                plane = (g.out_w, g.out_h, names, spec.antialias, samples)
                self.plane(built, head, common, plane, walked, reuse, walk)
            if reuse:
                self.tables.hold(key)
            return queue.download(result, dst, wait, uploads, errors), reuse

    def quads(self, built, staged, sw: int, sh: int, bg) -> list:
        """The quads of the input's three planes (Y of sw x sh, U and V at half
        size, packed I420 in ``staged``), padded for the edges mode with the
        background's codes ``bg`` (Y, Cb, Cr)."""
        queue, yl = self.queue, self.programs.yuv_lanes
        cw, ch = sw // 2, sh // 2
        planes_in = (  # (name, offset, width, height, background code) of each input plane
            ("quads_y", 0, sw, sh, bg[0]),
            ("quads_u", sw * sh, cw, ch, bg[1]),
            ("quads_v", sw * sh + cw * ch, cw, ch, bg[2]),
        )
        quads = []
        k = built.kernels["marble_quads"]
        for name, off, pw, ph, code in planes_in:
            buf = queue.buffer(name, (pw + 2) * (ph + 2) * 4)
            size = dict(off=np.int32(off), pw=np.int32(pw), ph=np.int32(ph))
            set_args(k, quads=buf, yuv=staged, **size, bg=np.uint32(code))
            queue.launch(k, (pw + yl) // yl * (ph + 1))
            quads.append(buf)
        return quads

    def plane(self, built, head: dict, common: dict, plane: tuple, walked, reuse, walk) -> None:
        """Queue one output plane (luma, or both chroma planes): ``head`` and
        ``common``, the plane kernels' arguments by name; ``plane``: its width, height,
        table names, antialiasing and samples buffer; from the ``walked``
        lattice, the table of reused maps (``reuse``; ``walk``: fill it first) or
        a fresh walk."""
        queue, lanes = self.queue, self.programs.lanes
        pw, ph, names, antialias, samples = plane
        if walked is not None:
            self.lattice.render_plane(built, head, walked, common)
        elif not reuse:
            k = built.kernels["marble_plane"]
            set_args(k, common, **head)
            queue.launch(k, -(-pw // lanes) * -(-ph // built.rows))
        else:
            table = self.tables.table(built, names, pw, ph, antialias, common, walk)
            k = built.kernels["marble_apply_plane"]
            taps, wts, tstride = table
            set_args(k, head, taps=taps, wts=wts, tstride=tstride, samples=samples)
            queue.launch(k, -(-pw // lanes) * ph)
