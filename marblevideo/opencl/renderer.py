"""The OpenCL renderer: frames of a recipe on one device.

Images are RGBA uint8 arrays of shape (H, W, 4), rows top to bottom; RGB and
grey inputs are widened to RGBA on upload. Video frames may instead come and
go as I420 (:meth:`Renderer.render_i420`): warped plane by plane where input
and output share a colour matrix (:mod:`~marblevideo.opencl.planar`), else
converted on the device. An input is sampled inside a one-pixel border that
the kernel fills for the edges mode.

A frame is drawn by one of the strategies: every subsample walked
(:class:`~marblevideo.opencl.walks.FreshWalk`), the full pattern only where a
pixel needs it (:class:`~marblevideo.opencl.walks.AdaptiveWalk`), fetched
from the tables of reused maps (:class:`~marblevideo.opencl.tables.ReusedMaps`),
or, for an animated frame over an input that asks for it (``lattice=True``),
interpolated from a walked lattice where that can be trusted
(:class:`~marblevideo.opencl.lattice.LatticeWalk`).
Programs come from :class:`~marblevideo.opencl.program.Programs`, buffers and
copies from :class:`~marblevideo.opencl.queue.DeviceQueue`.
"""

from __future__ import annotations

import functools
from contextlib import contextmanager

import numpy as np

from marblevideo.errors import DeviceError, UsageError
from marblevideo.limits import MAX_SIDE
from marblevideo.media.yuv import YuvMatrix, split_i420
from marblevideo.opencl.device import DeviceInfo, choose_device
from marblevideo.opencl.kernel_args import set_args, walk_args
from marblevideo.opencl.lattice import LatticeWalk
from marblevideo.opencl.planar import PlanarFrames
from marblevideo.opencl.program import Built, Programs, Structure, pack_params
from marblevideo.opencl.queue import DeviceQueue, float4, geometry_args
from marblevideo.opencl.strategy import Strategies
from marblevideo.opencl.tables import ReusedMaps
from marblevideo.opencl.walks import AdaptiveWalk, FreshWalk
from marblevideo.recipe.frame import FrameSpec, Geometry


def check_size(w: int, h: int) -> None:
    """UsageError for an output side outside 1..MAX_SIDE."""
    if not (0 < w <= MAX_SIDE and 0 < h <= MAX_SIDE):
        raise UsageError(f"output size {w}x{h} is outside 1..{MAX_SIDE} per side")


def packed_color(rgb) -> int:
    """An opaque colour (0..255 floats) as packed RGBA8, red in the low byte."""
    r, g, b = (int(round(float(c))) for c in rgb[:3])
    return r | g << 8 | b << 16 | 255 << 24


def to_rgba(image: np.ndarray) -> np.ndarray:
    """An (H, W, 4) C-contiguous uint8 view or copy of an RGBA, RGB or grey image."""
    if image.dtype != np.uint8:
        raise UsageError(f"images must be 8-bit, got {image.dtype}")
    if image.ndim == 2:
        image = image[:, :, None].repeat(3, axis=2)
    if image.ndim != 3 or image.shape[2] not in (3, 4):
        raise UsageError(f"images must be (H, W, 3|4), got shape {image.shape}")
    if image.shape[2] == 3:
        alpha = np.full(image.shape[:2] + (1,), 255, np.uint8)
        image = np.concatenate([image, alpha], axis=2)
    return np.ascontiguousarray(image)


def rgba_io(queue: DeviceQueue, rgba: np.ndarray | None, out, wait: bool, errors):
    """(put, fetch) of an RGBA frame for :meth:`Renderer._render`: the input
    ``rgba`` (None: a blank sheet) up, the result into ``out`` (or a new array)."""

    def put(built, padded, uploads: list) -> None:
        uploads.append(queue.put_rgba(rgba, padded))

    def fetch(built, dst, w: int, h: int, uploads: list):
        result = np.empty((h, w, 4), np.uint8) if out is None else out
        return queue.download(result, dst, wait, uploads, errors)

    return put, fetch


def i420_io(queue: DeviceQueue, yl: int, planes, matrices, out, wait: bool, errors):
    """(put, fetch) of an I420 frame converted on the device for
    :meth:`Renderer._render`: ``planes`` (Y, U, V; None: a blank sheet) up and
    to RGBA through ``matrices[0]``, the result to I420 through ``matrices[1]``
    (kernel matrices, :attr:`YuvMatrix.kernel_args`) into ``out``; ``yl``: the
    I420 kernels' lanes."""
    from pyopencl.cltypes import float16

    to_rgb, to_yuv = matrices

    def put(built, padded, uploads: list) -> None:
        sh, sw = planes[0].shape
        staged = queue.put_i420(planes, uploads)
        k = built.kernels["marble_from_i420"]
        first, row = np.int32(sw + 3), np.int32(sw + 2)  # pixel (0, 0) of the frame, a row
        size = dict(w=np.int32(sw), h=np.int32(sh))
        set_args(
            k, dst=padded, off=first, stride=row, yuv=staged, **size, m=to_rgb.view(float16)[0]
        )
        queue.launch(k, -(-sw // yl) * (sh // 2))

    def fetch(built, dst, w: int, h: int, uploads: list):
        result = np.empty((h * 3 // 2, w), np.uint8) if out is None else out
        staged = queue.buffer("i420_out", result.nbytes)
        k = built.kernels["marble_to_i420"]
        set_args(k, yuv=staged, src=dst, w=np.int32(w), h=np.int32(h), m=to_yuv.view(float16)[0])
        queue.launch(k, -(-w // yl) * (h // 2))
        return queue.download(result, staged, wait, uploads, errors)

    return put, fetch


def padded_input(queue: DeviceQueue, built: Built, size, put, background, uploads: list):
    """The buffer of an input of ``size`` (w, h) that ``put`` writes, inside a
    one-pixel border that marble_pad fills for the edges mode (``background``:
    0..255 RGB); a blank sheet (None) gets a placeholder."""
    if size is None:
        return queue.buffer("padded", 4)
    sw, sh = size
    src = queue.buffer("padded", (sw + 2) * (sh + 2) * 4)
    put(built, src, uploads)
    k = built.kernels["marble_pad"]
    set_args(k, src=src, sw=np.int32(sw), sh=np.int32(sh), bg=np.uint32(packed_color(background)))
    queue.launch(k, 2 * (sw + 2) + 2 * sh)
    return src


class Renderer:
    """Renders :class:`FrameSpec` s on one OpenCL device.

    ``device``: a choice as in :func:`marblevideo.opencl.device.choose_device`.
    ``lanes`` and ``chains`` override the vector width and the independent
    chains per work-item (defaults: :func:`~marblevideo.opencl.program.cpu_lanes`
    and :func:`~marblevideo.opencl.program.cpu_chains` on CPUs, 1 and 1 on
    GPUs). ``lanes`` is 1, 4, 8 or 16.
    ``adaptive`` samples the full antialiasing pattern only where a pixel's
    neighbourhood shows an ink edge or a strongly curved map, one walk
    elsewhere (see kernels/adaptive.cl); False evaluates the full pattern everywhere;
    None (default) is adaptive on blank sheets only, where it halves the time,
    while over an input its four bilinear fetches per pixel stay and the
    centre pass measured slower than the full pattern (BENCHMARKS.md); and
    after a frame that put most pixels on the full pattern anyway (a busy
    design: :data:`~marblevideo.opencl.walks.BUSY_SHARE`), the next frames of
    that size and program take the full pattern, every eighth adaptive again.
    ``reuse_maps``: over an input, when a frame's values, geometry and sizes
    equal the previous frame's (a static recipe over a video), where every
    subsample lands is recorded once and later frames only fetch and blend
    (within one level of a fresh walk; see kernels/tables.cl). False walks every frame.
    A render called with ``static=True`` (the caller knows that later frames
    repeat its values, as a static recipe over a video does) fills the table
    on its first frame already, instead of walking afresh and then again into
    the table on the second.
    ``loop_walk``: every recipe walks its ops in a loop (one program for all,
    built once), so that a recipe whose ops change is never rebuilt: for
    editors (``marblevideo design``); otherwise a program is built per recipe
    structure with its ops unrolled, and the loop is for long recipes only.
    ``profile``: time each kernel (DeviceQueue.kernel_times; for benchmarks).
    """

    def __init__(
        self,
        device: str | None = None,
        *,
        lanes: int | None = None,
        chains: int | None = None,
        adaptive: bool | None = None,
        reuse_maps: bool = True,
        loop_walk: bool = False,
        profile: bool = False,
    ):
        import pyopencl as cl

        self._cl = cl
        self.info: DeviceInfo = choose_device(device)
        try:
            self.context = cl.Context([self.info.device])
        except cl.Error as exc:
            raise DeviceError(f"cannot open OpenCL device {self.info.name}: {exc}") from None
        is_cpu = bool(self.info.device.type & cl.device_type.CPU)
        self.device_queue = DeviceQueue(self.context, self.info, is_cpu, profile)
        self.programs = Programs(self.context, self.info, lanes, chains, loop_walk)
        self.lanes, self.chains = self.programs.lanes, self.programs.chains
        self.yuv_lanes = self.programs.yuv_lanes
        self.adaptive = adaptive
        self.reuse_maps = reuse_maps
        self.tables = ReusedMaps(self.device_queue, self.lanes)
        self.fresh = FreshWalk(self.device_queue, self.lanes)
        self.adaptive_walk = AdaptiveWalk(self.device_queue, self.lanes)
        self.lattice_walk = LatticeWalk(self.device_queue, self.lanes, "GPU" in self.info.kind)
        self.planar = PlanarFrames(self.device_queue, self.programs, self.tables, self.lattice_walk)
        self.strategies = Strategies(self)
        #: whether the last render came from the table of reused maps
        self.last_reused = False

    @property
    def loop_walk(self) -> bool:
        """Whether every recipe walks its ops in a loop (see the class); settable."""
        return self.programs.loop

    @loop_walk.setter
    def loop_walk(self, on: bool) -> None:
        self.programs.loop = bool(on)

    @property
    def last_full_pixels(self) -> int | None:
        """Pixels the last render gave the full pattern, when it was adaptive (else None)."""
        return self.adaptive_walk.last_full_pixels

    def forget_frames(self) -> None:
        """Start a new job on this renderer (its context and programs kept): the
        next frame is drawn as a new renderer's first would be (the tables it holds
        stay valid; only which frame came last is forgotten)."""
        self.tables.forget_last()
        self.adaptive_walk.forget()

    def prebuild(self, structure: Structure) -> None:
        """Build ``structure``'s program in the background (see Programs.prebuild)."""
        self.programs.prebuild(structure)

    def kernel_for(self, structure: Structure) -> Built:
        """``structure``'s program, built on first use and cached."""
        return self.programs.get(structure)

    def build_program(self, source: str, options: list[str]):
        """A program of ``source`` for this device (see Programs.build_program)."""
        return self.programs.build_program(source, options)

    def render(
        self,
        spec: FrameSpec,
        geom: Geometry,
        image: np.ndarray | None = None,
        out: np.ndarray | None = None,
        *,
        static: bool = False,
        wait: bool = True,
        lattice: bool = False,
    ):
        """Render one frame: (geom.out_h, geom.out_w, 4) uint8 RGBA.

        ``image`` is the input (RGBA, RGB or grey uint8), or None for a blank
        sheet; ``out`` an optional destination array of the right shape;
        ``static``: later frames repeat these values (see the class).
        ``wait=False`` returns once the frame is queued, with a function that
        waits for it and returns it (see :meth:`render_i420`).
        ``lattice``: over an input, unless the maps are reused, interpolate the
        map from a walked lattice where it can be trusted (animated frames; see
        :mod:`~marblevideo.opencl.lattice`); False walks every subsample.
        """
        rgba = None if image is None else to_rgba(image)
        size = None if rgba is None else (rgba.shape[1], rgba.shape[0])
        put, fetch = rgba_io(self.device_queue, rgba, out, wait, self.errors)
        return self._render(spec, geom, size, put, fetch, static, lattice)

    def render_i420(
        self,
        spec: FrameSpec,
        geom: Geometry,
        planes,
        src_matrix: YuvMatrix | None,
        dst_matrix: YuvMatrix,
        out: np.ndarray | None = None,
        *,
        static: bool = False,
        wait: bool = True,
        lattice: bool = False,
    ):
        """:meth:`render` for 8-bit 4:2:0 video frames, converted on the device.

        ``planes``: the input as I420, packed or as planes (see
        :mod:`marblevideo.media.yuv`; padded rows are copied as they are, without
        a copy on the host), even-sized, in ``src_matrix``, or None for a blank
        sheet; returns the frame as packed I420 in ``dst_matrix``, shape
        (3 * out_h / 2, out_w), which must be even too. Equal, up to float
        rounding, to :func:`~marblevideo.reference.yuv.i420_to_rgba`,
        :meth:`render` and :func:`~marblevideo.reference.yuv.rgba_to_i420` in
        turn; only a third of the RGBA bytes cross to the device and back.

        When ``src_matrix`` equals ``dst_matrix`` the planes are warped as they
        are (:class:`~marblevideo.opencl.planar.PlanarFrames`): no conversion,
        one gather per bilinear footprint instead of four, and the same table of
        reused maps per plane.

        ``wait=False`` returns as soon as the frame is queued on the device, with
        a function that waits for it and returns the frame: the caller may queue
        the next frame first, so that the device does not idle while the host
        prepares it (the queue runs in order, so frames in flight share the
        buffers safely). ``planes`` must stay unchanged until then; the function
        holds them.
        """
        if geom.out_w % 2 or geom.out_h % 2:
            raise ValueError(f"I420 output needs even sizes, got {geom.out_w}x{geom.out_h}")
        self.adaptive_walk.last_full_pixels = None
        size, to_rgb = None, None
        if planes is not None:
            planes = split_i420(planes)
            sh, sw = planes[0].shape
            if src_matrix == dst_matrix:
                check_size(geom.out_w, geom.out_h)
                choose = functools.partial(self.strategies.choose, static=static, lattice=lattice)
                frame, self.last_reused = self.planar.render(
                    spec, geom, planes, dst_matrix, out, wait, self.errors, choose
                )
                return frame
            size, to_rgb = (sw, sh), src_matrix.kernel_args[0]
        matrices = (to_rgb, dst_matrix.kernel_args[1])
        io = i420_io(self.device_queue, self.yuv_lanes, planes, matrices, out, wait, self.errors)
        return self._render(spec, geom, size, *io, static, lattice)  # a blank sheet: no lattice

    def _render(
        self,
        spec: FrameSpec,
        geom: Geometry,
        size,
        put,
        fetch,
        static: bool = False,
        lattice: bool = False,
    ):
        """One RGBA frame over an input of ``size`` (w, h), or a blank sheet (None).

        ``put(built, padded, uploads)`` writes the input's RGBA pixels inside
        the one-pixel border of ``padded`` (rows of the input's width + 2
        pixels, the frame from pixel (1, 1) on); ``fetch(built, dst, w, h,
        uploads)`` turns the RGBA result into the return value (see
        DeviceQueue.download). ``uploads`` collects the events of the frame's
        copies from the host, which hold their arrays until copied.
        """
        queue = self.device_queue
        w, h = geom.out_w, geom.out_h
        check_size(w, h)
        self.adaptive_walk.last_full_pixels = None
        has_input = size is not None
        structure = Structure.of(spec, has_input)
        built = self.programs.get(structure)
        packed = pack_params(spec)
        maps, geo = geometry_args(geom)
        sw, sh = size if has_input else (1, 1)
        bg = [float(c) for c in spec.background]
        key = (structure, packed.key, geo.tobytes(), w, h, sw, sh) if has_input else None
        drawn = self.strategies.choose(
            key,
            self.tables.nbytes(spec.antialias, w, h),
            packed,
            static=static,
            lattice=lattice,
            adaptive=lambda: self.strategies.adaptive(spec, has_input, w, h, structure),
        )
        self.last_reused = drawn == "tables"
        with self.errors():
            uploads: list = []
            pbuf, lbuf = queue.put_params(packed, uploads)
            src = padded_input(queue, built, size, put, bg, uploads)
            dst = queue.buffer("dst", w * h * 4)
            samples = queue.samples(spec.antialias)
            bgc = float4(bg + [255.0])
            common = walk_args(src, np.int32(sw), np.int32(sh), pbuf, samples, maps, bgc, lbuf)
            if drawn == "tables":
                self.tables.render(built, dst, w, h, common, key)
            elif drawn == "lattice":
                walked = self.lattice_walk.walk(built, geom, pbuf, lbuf)
                self.lattice_walk.render(built, dst, w, h, walked, common)
            elif drawn == "adaptive":
                self.adaptive_walk.render(built, dst, w, h, common, pbuf, maps, has_input)
            else:
                self.fresh.render(built, dst, w, h, common)
            return fetch(built, dst, w, h, uploads)

    @contextmanager
    def errors(self):
        """OpenCL errors as DeviceError, forgetting the tables (one being walked
        may be half-written)."""
        try:
            yield
        except self._cl.Error as exc:
            self.tables.hold(None)
            raise DeviceError(f"OpenCL error on {self.info.name}: {exc}") from None
