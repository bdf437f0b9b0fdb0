"""The OpenCL renderer: one kernel evaluates a frame's whole inverse walk.

A recipe's *structure* (op types in order, antialiasing pattern, edges mode,
blank sheet or input) is built into a program once; the per-frame values (a
:class:`~marblevideo.recipe.frame.FrameSpec`) are packed into a small float buffer by
:func:`pack_params`, so animating a recipe never recompiles. Programs are
cached per structure and their kernel fetched once.

Images are RGBA uint8 arrays of shape (H, W, 4), rows top to bottom; RGB and
grey inputs are widened to RGBA on upload. Video frames may instead come and
go as I420 (:meth:`Renderer.render_i420`): warped plane by plane where input
and output share a colour matrix, else converted on the device. An input is
sampled inside a one-pixel border that the kernel fills for the edges mode.
On CPU devices the kernel runs vector code as wide as the device's native
float vectors (:func:`cpu_lanes`: 16 lanes on AVX-512, 8 on AVX2, 4 on SSE)
with several independent chains per work-item (see shared/PERF-NOTES.md); on
GPUs one pixel per work-item.

Programs build silently: the OpenCL compiler's warnings are switched off
(``-w``) and its log is kept, unless the ``marblevideo`` logger is enabled for
DEBUG (the CLI's ``--verbose``), which builds with warnings and logs the build
log; a failed build raises a one-line DeviceError naming a file that holds the
whole log.
"""

from __future__ import annotations

import logging
import os
import tempfile
import threading
import time
import warnings
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from marblevideo.errors import DeviceError, UsageError
from marblevideo.media.yuv import YuvMatrix, chroma_geometry, coded_spec, split_i420
from marblevideo.opencl.device import DeviceInfo, choose_device
from marblevideo.ops import COLOR_SLOTS, PSTRIDE, REGISTRY, is_ink, op_def
from marblevideo.recipe.antialias import pattern
from marblevideo.recipe.frame import EDGE_MODES, FrameSpec, Geometry

#: Recipes longer than this walk their ops in a loop instead of unrolled code.
UNROLL_LIMIT = 48
#: Work-group size of marble_classify (its list takes one global atomic per group).
CLASSIFY_GROUP = 64
#: Work-group size of the other kernels on CPU devices (GPUs choose their own).
CPU_GROUP = 128
#: Largest output or input side accepted (OpenCL buffers and int indices).
MAX_SIDE = 1 << 15
#: Pixels whose walks a CPU work-item keeps in flight (lanes x chains): 4 chains
#: of 16 lanes with AVX-512; with 8 lanes, 8 chains did as well as 16 lanes
#: (BENCHMARKS.md, vector width).
CPU_PIXELS_IN_FLIGHT = 64
#: Environment variable that overrides the vector width on CPU devices (4, 8 or 16).
LANES_VARIABLE = "MARBLEVIDEO_LANES"
#: Vector widths the kernel is written for.
VECTOR_WIDTHS = (4, 8, 16)
#: Largest table of reused maps (bytes: 8 per subsample per pixel; 1080p RGSS
#: takes 66 MB). Frames needing more are walked afresh every time.
TABLE_LIMIT = 512 << 20


log = logging.getLogger("marblevideo.opencl")


def cpu_lanes(native_width: int, override: str | None = None) -> int:
    """Pixels per work-item on a CPU device whose native float vector width is
    ``native_width`` (what ``CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT`` reports: 16
    with AVX-512, 8 with AVX/AVX2, 4 with SSE or NEON): that width, within 4..16.
    A wider vector than the CPU's registers is split by the compiler and, on
    x86, changes the calling convention (clang warns). ``override``: the value
    of :data:`LANES_VARIABLE`, for measuring one width against another."""
    if override:
        try:
            lanes = int(override)
        except ValueError:
            lanes = 0
        if lanes not in VECTOR_WIDTHS:
            widths = ", ".join(map(str, VECTOR_WIDTHS))
            raise UsageError(f"{LANES_VARIABLE}: expected one of {widths}, got {override!r}")
        return lanes
    return max(w for w in VECTOR_WIDTHS if w <= max(native_width, VECTOR_WIDTHS[0]))


def cpu_chains(lanes: int) -> int:
    """Independent chains per work-item on a CPU for vectors of ``lanes``: enough
    for CPU_PIXELS_IN_FLIGHT pixels (4 chains of 16 lanes, 8 of 8), at most 8
    (more spill the 16 vector registers of AVX2 and SSE)."""
    return max(1, min(8, CPU_PIXELS_IN_FLIGHT // max(lanes, 1)))


def kernel_source(name: str = "marble.cl") -> str:
    """An OpenCL source (a path under kernels/) from the installed package, or from
    the repository's kernels/."""
    packaged = resources.files("marblevideo") / "kernels" / name
    if packaged.is_file():
        return packaged.read_text()
    return (Path(__file__).resolve().parents[2] / "kernels" / name).read_text()


def program_source() -> str:
    """The program's source without its generated header: the prelude, each op
    family's sections (kernels/ops/<family>.cl, in registry order) and marble.cl."""
    families = dict.fromkeys(d.family for d in REGISTRY.values())
    parts = ["prelude.cl", *(f"ops/{family}.cl" for family in families), "marble.cl"]
    return "\n".join(kernel_source(name) for name in parts)


def pack_params(spec: FrameSpec) -> np.ndarray:
    """Per-frame op values as float32, PSTRIDE per op: each op's definition packs
    its floats (:attr:`marblevideo.ops.OpDef.pack`; no library trigonometry is
    left for the kernel), the last float is its type code."""
    out = np.zeros((max(len(spec.ops), 1), PSTRIDE), dtype=np.float64)
    lists: list[float] = []
    for i, op in enumerate(spec.ops):
        definition = op_def(op.type)
        row = definition.packed(op.values, lists)
        out[i, : len(row)] = row
        out[i, PSTRIDE - 1] = definition.code
    # Products of valid values (radius**2, alpha * lambda) can pass float32's range:
    # saturate them rather than hand the kernel inf (and inf * 0 = NaN).
    f32 = float(np.finfo(np.float32).max)
    return np.clip(out, -f32, f32).astype(np.float32).ravel()


@dataclass(frozen=True)
class Structure:
    """What a program is built for; everything else is a per-frame value."""

    types: tuple[str, ...]
    antialias: str
    edges: str
    has_input: bool

    @classmethod
    def of(cls, spec, has_input: bool) -> Structure:
        """The structure of a FrameSpec or a Recipe (both have ops with a type,
        antialias and edges)."""
        return cls(tuple(op.type for op in spec.ops), spec.antialias, spec.edges, has_input)


def walk_source(types: tuple[str, ...]) -> str:
    """The generated header that bakes a recipe's structure into the program: WALK
    calls every op's section, last op first, and INK resolves the ink ops' hits
    (see kernels/marble.cl); above UNROLL_LIMIT ops both loop over the ops and
    switch on the type code, with one case per registered op type."""
    if len(types) > UNROLL_LIMIT:
        cases = " ".join(f"case {d.code}: OP(i, {d.type}) break;" for d in REGISTRY.values())
        ink = " || ".join(f"code_ == {d.code}" for d in REGISTRY.values() if d.ink)
        return (
            f"#define NOPS {len(types)}\n"
            "#define WALK for (int i = NOPS - 1; i >= 0; i--) "
            f"{{ switch ((int)PARAMS(i)[PSTRIDE - 1]) {{ {cases} }} }}\n"
            "#define INK for (int i = 0; i < NOPS; i++) "
            f"{{ const int code_ = (int)PARAMS(i)[PSTRIDE - 1]; if ({ink}) INK_COLOR(i) }}\n"
        )
    walk = " ".join(f"OP({i}, {op_def(t).type})" for i, t in reversed(list(enumerate(types))))
    ink = " ".join(f"INK_COLOR({i})" for i, t in enumerate(types) if is_ink(t))
    return f"#define WALK {walk}\n#define INK {ink}\n"


def _pad(n: int, multiple: int = 64) -> int:
    """Global sizes are padded to a multiple of 64 (PoCL picks a local size dividing it)."""
    return max(multiple, -(-n // multiple) * multiple)


def _maps(geo: np.ndarray) -> tuple:
    """The kernel arguments of a packed geometry (8 float32: output -> canvas,
    canvas -> input), as two float4 (no wider vectors: see marble.cl)."""
    import pyopencl.cltypes as cltypes

    return geo[:4].view(cltypes.float4)[0], geo[4:].view(cltypes.float4)[0]


def _check_size(w: int, h: int) -> None:
    if not (0 < w <= MAX_SIDE and 0 < h <= MAX_SIDE):
        raise UsageError(f"output size {w}x{h} is outside 1..{MAX_SIDE} per side")


def _packed(rgb) -> int:
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


class Renderer:
    """Renders :class:`FrameSpec` s on one OpenCL device.

    ``device``: a choice as in :func:`marblevideo.device.choose_device`.
    ``lanes`` and ``chains`` override the vector width and the independent
    chains per work-item (defaults: :func:`cpu_lanes` and :func:`cpu_chains` on CPUs, 1 and 1
    on GPUs). ``lanes`` is 1, 4, 8 or 16.
    ``adaptive`` samples the full antialiasing pattern only where a pixel's
    neighbourhood shows an ink edge or a strongly curved map, one walk
    elsewhere (see marble.cl); False evaluates the full pattern everywhere;
    None (default) is adaptive on blank sheets only, where it halves the time,
    while over an input its four bilinear fetches per pixel stay and the
    centre pass measured slower than the full pattern (BENCHMARKS.md).
    ``reuse_maps``: over an input, when a frame's values, geometry and sizes
    equal the previous frame's (a static recipe over a video), where every
    subsample lands is recorded once and later frames only fetch and blend
    (within one level of a fresh walk; see marble.cl). False walks every frame.
    A render called with ``static=True`` (the caller knows that later frames
    repeat its values, as a static recipe over a video does) fills the table
    on its first frame already, instead of walking afresh and then again into
    the table on the second.
    """

    def __init__(
        self,
        device: str | None = None,
        *,
        lanes: int | None = None,
        chains: int | None = None,
        adaptive: bool | None = None,
        reuse_maps: bool = True,
    ):
        import pyopencl as cl

        self._cl = cl
        self.info: DeviceInfo = choose_device(device)
        dev = self.info.device
        try:
            self.context = cl.Context([dev])
            self.queue = cl.CommandQueue(self.context)
        except cl.Error as exc:
            raise DeviceError(f"cannot open OpenCL device {self.info.name}: {exc}") from None
        is_cpu = bool(dev.type & cl.device_type.CPU)
        native = max(int(dev.native_vector_width_float), int(dev.preferred_vector_width_float))
        vectors = cpu_lanes(native, os.environ.get(LANES_VARIABLE)) if is_cpu else 16
        lanes = lanes or (vectors if is_cpu else 1)
        if lanes not in (1, *VECTOR_WIDTHS):
            raise UsageError(f"lanes must be 1, 4, 8 or 16, got {lanes!r}")
        self.lanes = lanes
        #: the I420 and quad kernels' width: ``lanes``, else the CPU's vectors, 16 on GPUs
        self.yuv_lanes = lanes if lanes > 1 else vectors
        #: independent chains per work-item: CPU_PIXELS_IN_FLIGHT pixels' walks
        #: side by side (a walk is a chain of dependent operations)
        self.chains = chains or (cpu_chains(lanes) if is_cpu else 1)
        log.debug(
            "rendering on %s %s (%s): %d lane%s x %d chain%s per work-item "
            "(native float vectors: %d)",
            self.info.label,
            self.info.name,
            self.info.platform,
            self.lanes,
            "s" * (self.lanes != 1),
            self.chains,
            "s" * (self.chains != 1),
            native,
        )
        self.adaptive = adaptive
        self.reuse_maps = reuse_maps
        #: what the last frame over an input was walked for, and what the table holds
        self._last_map: tuple | None = None
        self._table_map: tuple | None = None
        #: whether the last render came from the table of reused maps
        self.last_reused = False
        self._table_limit = min(TABLE_LIMIT, dev.max_mem_alloc_size)
        self._classify_group = min(CLASSIFY_GROUP, dev.max_work_group_size)
        #: work-group size on CPUs; PoCL's own choice made 15 groups of a 720p
        #: frame, which two cores shared unevenly (128 measured 5-10% faster)
        self._group = min(CPU_GROUP, dev.max_work_group_size) if is_cpu else None
        #: pixels rendered with the full pattern by the last adaptive render
        self.last_full_pixels: int | None = None
        self._source = program_source()
        self._kernels: dict[tuple, object] = {}
        self._build_lock = threading.Lock()
        self._buffers: dict[str, tuple[int, object]] = {}
        self._samples: dict[str, object] = {}

    # -- programs ---------------------------------------------------------
    def _layout(self, nsamples: int) -> tuple[int, int]:
        """(rows per work-item, chains) for a pattern of ``nsamples``: every chain
        busy, a subsample of a row each (several rows where the pattern has
        fewer subsamples than the chains)."""
        if self.lanes == 1 or self.chains == 1:
            return 1, 1
        if nsamples == 1:
            return self.chains, self.chains
        if nsamples < self.chains and self.chains % nsamples == 0:
            return self.chains // nsamples, self.chains
        if nsamples <= 5 or nsamples % self.chains:
            return 1, nsamples
        return 1, self.chains

    def prebuild(self, structure: Structure) -> None:
        """Start building ``structure``'s program in a background thread, where the
        OpenCL compiler runs without the GIL: a caller that opens its input and
        decoder meanwhile starts sooner. A failure there is left for the first
        render, which builds again and reports it. The thread is not a daemon: a
        process that exits meanwhile waits for the build (killing a thread inside
        the OpenCL compiler aborts the process)."""

        def build() -> None:
            with suppress(Exception):  # reported by the render that needs the program
                self.kernel_for(structure)

        threading.Thread(target=build, name="marblevideo-build").start()

    def kernel_for(self, structure: Structure):
        """The kernel for ``structure``, built on first use and cached (one build at
        a time: a render waits for a :meth:`prebuild` of the same program)."""
        key = (structure,)
        kernel = self._kernels.get(key)
        if kernel is not None:
            return kernel
        with self._build_lock:
            kernel = self._kernels.get(key)
            return kernel if kernel is not None else self._build(structure)

    def _build(self, structure: Structure):
        """Build and cache ``structure``'s program (the caller holds the build lock)."""
        key = (structure,)
        cl = self._cl
        nsamples = len(pattern(structure.antialias))
        rows, chains = self._layout(nsamples)
        options = [
            f"-DLANES={self.lanes}",
            f"-DCHAINS={chains}",
            f"-DROWS={rows}",
            f"-DNSAMPLES={nsamples}",
            f"-DHAS_INPUT={int(structure.has_input)}",
            f"-DEDGES={EDGE_MODES.index(structure.edges)}",
            f"-DYLANES={self.yuv_lanes}",
            f"-DPSTRIDE={PSTRIDE}",
            f"-DCOLOR_SLOT={COLOR_SLOTS[0]}",
        ]
        program = self.build_program(walk_source(structure.types) + self._source, options)
        names = ("marble", "marble_centres", "marble_classify", "marble_list")
        names += (
            "marble_table",
            "marble_apply",
            "marble_pad",
            "marble_from_i420",
            "marble_to_i420",
            "marble_quads",
            "marble_plane",
            "marble_apply_plane",
        )
        kernel = ({n: cl.Kernel(program, n) for n in names}, rows, chains)
        self._kernels[key] = kernel
        return kernel

    def build_program(self, source: str, options: list[str]):
        """A program of ``source`` built for this renderer's device with ``options``:
        silently (``-w``; pyopencl's CompilerWarning dropped) unless the
        ``marblevideo`` logger is enabled for DEBUG, which gets the build log. A
        failed build raises DeviceError in one line (see the module)."""
        cl = self._cl
        verbose = log.isEnabledFor(logging.DEBUG)
        began = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", cl.CompilerWarning)
                program = cl.Program(self.context, source).build(
                    options=options if verbose else [*options, "-w"]
                )
        except cl.Error as exc:
            raise DeviceError(self._build_failure(str(exc), source, options)) from None
        if verbose:
            text = program.get_build_info(self.info.device, cl.program_build_info.LOG)
            log.debug(
                "built the kernels for %s in %.2f s (%s)%s",
                self.info.name,
                time.perf_counter() - began,
                " ".join(options),
                f"; build log:\n{text.strip()}" if text.strip() else "; empty build log",
            )
        return program

    def _build_failure(self, message: str, source: str, options: list[str]) -> str:
        """The one-line error of a failed build; the whole log, the options and the
        source go to a file it names."""
        lines = [line.strip() for line in message.strip().splitlines() if line.strip()]
        first = next((line for line in lines if "error" in line.lower() and ":" in line), None)
        first = first or (lines[0] if lines else "no log")
        try:
            fd, path = tempfile.mkstemp(prefix="marblevideo-build-", suffix=".log")
            with os.fdopen(fd, "w") as f:
                f.write(f"{message}\n\noptions: {' '.join(options)}\n\n{source}")
            where = f" (full log: {path})"
        except OSError:
            where = ""
        log.debug("build log:\n%s", message)
        return f"OpenCL build failed on {self.info.name}: {first[:300]}{where}"

    # -- buffers ----------------------------------------------------------
    def _buffer(self, name: str, nbytes: int):
        nbytes = max(int(nbytes), 4)
        have = self._buffers.get(name)
        if have is None or have[0] < nbytes:
            flags = self._cl.mem_flags.READ_WRITE
            try:
                buf = self._cl.Buffer(self.context, flags, nbytes)
            except self._cl.Error as exc:
                raise DeviceError(
                    f"cannot allocate {nbytes} bytes on {self.info.name} ({exc}); "
                    "try a smaller --size"
                ) from None
            self._buffers[name] = (nbytes, buf)
            return buf
        return have[1]

    def _sample_buffer(self, name: str):
        buf = self._samples.get(name)
        if buf is None:
            data = pattern(name).astype(np.float32).ravel()
            mf = self._cl.mem_flags
            buf = self._cl.Buffer(self.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=data)
            self._samples[name] = buf
        return buf

    # -- rendering --------------------------------------------------------
    def _launch(self, kernel, n: int) -> None:
        """Enqueue ``n`` work-items of ``kernel`` (padded; surplus items return at once)."""
        group = self._group
        self._cl.enqueue_nd_range_kernel(
            self.queue, kernel, (_pad(n, group or 64),), None if group is None else (group,)
        )

    def render(
        self,
        spec: FrameSpec,
        geom: Geometry,
        image: np.ndarray | None = None,
        out: np.ndarray | None = None,
        *,
        static: bool = False,
        wait: bool = True,
    ):
        """Render one frame: (geom.out_h, geom.out_w, 4) uint8 RGBA.

        ``image`` is the input (RGBA, RGB or grey uint8), or None for a blank
        sheet; ``out`` an optional destination array of the right shape;
        ``static``: later frames repeat these values (see the class).
        ``wait=False`` returns once the frame is queued, with a function that
        waits for it and returns it (see :meth:`render_i420`).
        """
        rgba = None if image is None else to_rgba(image)
        size = None if rgba is None else (rgba.shape[1], rgba.shape[0])

        def put(kernels, padded, uploads: list) -> None:
            uploads.append(self._put_rgba(rgba, padded))

        def fetch(kernels, dst, w: int, h: int, uploads: list):
            result = np.empty((h, w, 4), np.uint8) if out is None else out
            return self._download(result, dst, wait, uploads)

        return self._render(spec, geom, size, put, fetch, static)

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
    ):
        """:meth:`render` for 8-bit 4:2:0 video frames, converted on the device.

        ``planes``: the input as I420, packed or as planes (see
        :mod:`marblevideo.media.yuv`; padded rows are copied as they are, without a
        copy on the host), even-sized, in ``src_matrix``, or None for a blank
        sheet; returns the frame as packed I420
        in ``dst_matrix``, shape (3 * out_h / 2, out_w), which must be even too.
        Equal, up to float rounding, to :func:`~marblevideo.yuv.i420_to_rgba`,
        :meth:`render` and :func:`~marblevideo.yuv.rgba_to_i420` in turn; only a
        third of the RGBA bytes cross to the device and back.

        When ``src_matrix`` equals ``dst_matrix`` the planes are warped as they
        are (:func:`~marblevideo.yuv.render_planes` is the reference): no
        conversion, one gather per bilinear footprint instead of four, and the
        same table of reused maps per plane.

        ``wait=False`` returns as soon as the frame is queued on the device, with
        a function that waits for it and returns the frame: the caller may queue
        the next frame first, so that the device does not idle while the host
        prepares it (the queue runs in order, so frames in flight share the
        buffers safely). ``planes`` must stay unchanged until then; the function
        holds them.
        """
        cl = self._cl
        if geom.out_w % 2 or geom.out_h % 2:
            raise ValueError(f"I420 output needs even sizes, got {geom.out_w}x{geom.out_h}")
        size = None
        if planes is not None:
            planes = split_i420(planes)
            sh, sw = planes[0].shape
            if src_matrix == dst_matrix:
                return self._render_planes(spec, geom, planes, dst_matrix, out, static, wait)
            size, to_rgb = (sw, sh), src_matrix.kernel_args[0]
        to_yuv = dst_matrix.kernel_args[1]

        def put(kernels, padded, uploads: list) -> None:
            staged = self._put_i420(planes, uploads)
            k = kernels["marble_from_i420"]
            k.set_args(
                padded,
                np.int32(sw + 3),  # pixel (0, 0) of the frame
                np.int32(sw + 2),
                staged,
                np.int32(sw),
                np.int32(sh),
                to_rgb.view(cl.cltypes.float16)[0],
            )
            self._launch(k, -(-sw // self.yuv_lanes) * (sh // 2))

        def fetch(kernels, dst, w: int, h: int, uploads: list):
            result = np.empty((h * 3 // 2, w), np.uint8) if out is None else out
            staged = self._buffer("i420_out", result.nbytes)
            k = kernels["marble_to_i420"]
            k.set_args(staged, dst, np.int32(w), np.int32(h), to_yuv.view(cl.cltypes.float16)[0])
            self._launch(k, -(-w // self.yuv_lanes) * (h // 2))
            return self._download(result, staged, wait, uploads)

        return self._render(spec, geom, size, put, fetch, static)

    def _render(self, spec: FrameSpec, geom: Geometry, size, put, fetch, static: bool = False):
        """One frame over an input of ``size`` (w, h), or a blank sheet (None).

        ``put(kernels, padded, uploads)`` writes the input's RGBA pixels inside
        the one-pixel border of ``padded`` (rows of the input's width + 2
        pixels, the frame from pixel (1, 1) on); ``fetch(kernels, dst, w, h,
        uploads)`` turns the RGBA result into the return value (see
        :meth:`_download`). ``uploads`` collects the events of the frame's
        copies from the host, which hold their arrays until copied: dropping
        one would wait for it, and so for every frame queued before it.
        """
        cl = self._cl
        w, h = geom.out_w, geom.out_h
        _check_size(w, h)
        has_input = size is not None
        structure = Structure.of(spec, has_input)
        kernels, rows, chains = self.kernel_for(structure)
        queue = self.queue
        params = pack_params(spec)
        geo = np.array([*geom.to_canvas, *geom.to_input], dtype=np.float32)
        sw, sh = size if has_input else (1, 1)
        bg = [float(c) for c in spec.background]
        reuse = False
        if has_input and self.reuse_maps:
            key = (structure, params.tobytes(), geo.tobytes(), w, h, sw, sh)
            reuse = self._maps_reused(key, self._table_bytes(spec.antialias, w, h), static)
        self.last_reused = reuse
        with self._device_errors():
            pbuf = self._buffer("params", params.nbytes)
            uploads = [cl.enqueue_copy(queue, pbuf, params, is_blocking=False)]
            if has_input:  # inside a border that marble_pad fills for the edges mode
                src = self._buffer("padded", (sw + 2) * (sh + 2) * 4)
                put(kernels, src, uploads)
                k = kernels["marble_pad"]
                k.set_args(src, np.int32(sw), np.int32(sh), np.uint32(_packed(bg)))
                self._launch(k, 2 * (sw + 2) + 2 * sh)
            else:
                src = self._buffer("padded", 4)
            dst = self._buffer("dst", w * h * 4)
            common = (
                src,
                np.int32(sw),
                np.int32(sh),
                pbuf,
                self._sample_buffer(spec.antialias),
                *_maps(geo),
                np.array(bg + [255.0], dtype=np.float32).view(cl.cltypes.float4)[0],
            )
            adaptive = self.adaptive if self.adaptive is not None else not has_input
            if reuse:
                self._render_from_table(kernels, rows, dst, w, h, common, key)
            elif adaptive and len(pattern(spec.antialias)) > 1:
                self._render_adaptive(
                    kernels, (rows, chains), dst, w, h, common, pbuf, geo, has_input
                )
            else:
                k = kernels["marble"]
                k.set_args(dst, np.int32(w), np.int32(h), *common)
                self._launch(k, -(-w // self.lanes) * -(-h // rows))
            return fetch(kernels, dst, w, h, uploads)

    def _render_planes(
        self,
        spec: FrameSpec,
        geom: Geometry,
        planes: tuple[np.ndarray, np.ndarray, np.ndarray],
        matrix: YuvMatrix,
        out,
        static: bool = False,
        wait: bool = True,
    ):
        """:meth:`render_i420` plane by plane, in ``matrix`` throughout."""
        cl, queue = self._cl, self.queue
        w, h = geom.out_w, geom.out_h
        sh, sw = planes[0].shape
        _check_size(w, h)
        coded = coded_spec(spec, matrix)
        structure = Structure.of(coded, True)
        kernels, rows, chains = self.kernel_for(structure)
        params = pack_params(coded)
        luma, chroma = geom, chroma_geometry(geom)
        geos = [np.array([*g.to_canvas, *g.to_input], np.float32) for g in (luma, chroma)]
        key = ("planes", structure, params.tobytes(), geos[0].tobytes(), w, h, sw, sh)
        reuse = False
        if self.reuse_maps:
            nbytes = sum(
                self._table_bytes(spec.antialias, g.out_w, g.out_h) for g in (luma, chroma)
            )
            reuse = self._maps_reused(key, nbytes, static)
        self.last_reused = reuse
        result = np.empty((h * 3 // 2, w), np.uint8) if out is None else out
        bg = coded.background
        with self._device_errors():
            pbuf = self._buffer("params", params.nbytes)
            # the uploads' events hold their host arrays until the copies are done
            uploads = [cl.enqueue_copy(queue, pbuf, params, is_blocking=False)]
            staged = self._put_i420(planes, uploads)
            dst = self._buffer("i420_out", result.nbytes)
            samples = self._sample_buffer(spec.antialias)
            bgc = np.array([*bg, 255.0], np.float32).view(cl.cltypes.float4)[0]
            cw, ch = sw // 2, sh // 2
            planes_in = (  # (name, offset, width, height, background code) of each input plane
                ("quads_y", 0, sw, sh, bg[0]),
                ("quads_u", sw * sh, cw, ch, bg[1]),
                ("quads_v", sw * sh + cw * ch, cw, ch, bg[2]),
            )
            quads = []
            k = kernels["marble_quads"]
            for name, off, pw, ph, code in planes_in:
                buf = self._buffer(name, (pw + 2) * (ph + 2) * 4)
                k.set_args(buf, staged, np.int32(off), np.int32(pw), np.int32(ph), np.uint32(code))
                self._launch(k, (pw + self.yuv_lanes) // self.yuv_lanes * (ph + 1))
                quads.append(buf)
            # luma, then both chroma planes at the same points: (geometry, its packed
            # maps, output offsets, input plane size, quads, chroma flag, table names)
            luma_job = (luma, geos[0], (0, 0), (sw, sh), quads[0], quads[0], 0, ("taps", "wts"))
            chroma_offsets = (w * h, w * h * 5 // 4)
            chroma_job = (
                chroma,
                geos[1],
                chroma_offsets,
                (cw, ch),
                *quads[1:],
                1,
                ("ctaps", "cwts"),
            )
            walk = reuse and self._table_map != key
            for g, geo, offsets, in_size, q0, q1, is_chroma, names in (luma_job, chroma_job):
                pw, ph = g.out_w, g.out_h
                head = (dst, *map(np.int32, offsets), np.int32(pw), np.int32(ph), q0, q1)
                head += (np.int32(is_chroma),)
                common = (q0, *map(np.int32, in_size), pbuf, samples)
                common += (*_maps(geo), bgc)
                if not reuse:
                    k = kernels["marble_plane"]
                    k.set_args(*head, *common)
                    self._launch(k, -(-pw // self.lanes) * -(-ph // rows))
                    continue
                table = self._walked_table(
                    kernels, rows, names, pw, ph, spec.antialias, common, walk
                )
                k = kernels["marble_apply_plane"]
                k.set_args(*head, *table, samples)
                self._launch(k, -(-pw // self.lanes) * ph)
            if reuse:
                self._table_map = key
            return self._download(result, dst, wait, uploads)

    def _download(self, result: np.ndarray, dst, wait: bool, uploads: list):
        """Copy the device buffer ``dst`` into ``result`` and return it; or, unless
        ``wait``, queue the copy and return a function that waits for it and
        returns ``result``, holding ``uploads`` (the events of the frame's copies
        from the host, which hold their arrays) until then."""
        download = self._cl.enqueue_copy(self.queue, result, dst, is_blocking=wait)
        if wait:
            return result

        def finish() -> np.ndarray:
            with self._device_errors():
                download.wait()
            uploads.clear()
            return result

        return finish

    @contextmanager
    def _device_errors(self):
        """OpenCL errors as DeviceError, forgetting the table (a table being walked
        may be half-written)."""
        try:
            yield
        except self._cl.Error as exc:
            self._table_map = None
            raise DeviceError(f"OpenCL error on {self.info.name}: {exc}") from None

    def _maps_reused(self, key: tuple, table_bytes: int, static: bool = False) -> bool:
        """Whether a frame whose maps are ``key`` is drawn from the tables: it lands
        where the last frame's did (or, ``static``, later frames will land where it
        does) and its tables (``table_bytes`` in one buffer of each pair) fit; ``key``
        becomes the last frame's."""
        reuse = (static or key == self._last_map) and table_bytes <= self._table_limit
        self._last_map = key
        return reuse

    def _put_rgba(self, rgba: np.ndarray, padded):
        """Copy ``rgba`` inside the one-pixel border of ``padded``; the copy's event."""
        sh, sw = rgba.shape[:2]
        return self._cl.enqueue_copy(
            self.queue,
            padded,
            rgba,
            buffer_origin=(4, 1),
            host_origin=(0, 0),
            region=(sw * 4, sh),
            buffer_pitches=((sw + 2) * 4,),
            host_pitches=(sw * 4,),
            is_blocking=False,
        )

    def _put_i420(self, planes: tuple[np.ndarray, np.ndarray, np.ndarray], events: list):
        """The buffer ``i420_in`` holding ``planes`` packed (see marblevideo.media.yuv);
        rows padded on the host are copied by a rectangle copy, not packed first.
        The copies' events are appended to ``events``."""
        cl = self._cl
        staged = self._buffer("i420_in", sum(p.shape[0] * p.shape[1] for p in planes))
        at = 0
        for plane in planes:
            ph, pw = plane.shape
            pitch = plane.strides[0]
            if pitch == pw:
                event = cl.enqueue_copy(self.queue, staged, plane, dst_offset=at, is_blocking=False)
            else:  # the bytes from the first row's start to the last row's end
                span = np.lib.stride_tricks.as_strided(
                    plane, shape=((ph - 1) * pitch + pw,), strides=(1,), writeable=False
                )
                event = cl.enqueue_copy(
                    self.queue,
                    staged,
                    span,
                    buffer_origin=(at, 0),
                    host_origin=(0, 0),
                    region=(pw, ph),
                    buffer_pitches=(pw,),
                    host_pitches=(pitch,),
                    is_blocking=False,
                )
            events.append(event)
            at += pw * ph
        return staged

    def _table_stride(self, w: int) -> int:
        return -(-w // self.lanes) * self.lanes

    def _table_bytes(self, antialias: str, w: int, h: int) -> int:
        """Bytes of each of the two table buffers of a w x h output."""
        return len(pattern(antialias)) * h * self._table_stride(w) * 4

    def _walked_table(self, kernels, rows, names, w, h, antialias, common, walk) -> tuple:
        """(taps, wts, row stride) of the table of a w x h output in the buffers
        ``names``, walked first by marble_table over ``common`` when ``walk``."""
        stride = self._table_stride(w)
        nbytes = self._table_bytes(antialias, w, h)
        taps, wts = (self._buffer(name, nbytes) for name in names)
        if walk:
            k = kernels["marble_table"]
            k.set_args(taps, wts, np.int32(w), np.int32(h), np.int32(stride), *common)
            self._launch(k, -(-w // self.lanes) * -(-h // rows))
        return taps, wts, np.int32(stride)

    def _render_from_table(self, kernels, rows, dst, w, h, common, key) -> None:
        """Fetch and blend from the table, walking it first if it holds other maps."""
        antialias = key[0].antialias
        walk = self._table_map != key
        taps, wts, stride = self._walked_table(
            kernels, rows, ("taps", "wts"), w, h, antialias, common, walk
        )
        self._table_map = key
        src, sw, samples = common[0], common[1], common[4]
        k = kernels["marble_apply"]
        k.set_args(dst, np.int32(w), np.int32(h), taps, wts, stride, src, sw, samples)
        self._launch(k, -(-w // self.lanes) * h)

    def _render_adaptive(self, kernels, layout, dst, w, h, common, pbuf, geo, has_input) -> None:
        """The three passes of adaptive antialiasing (see marble.cl)."""
        cl, queue, lanes = self._cl, self.queue, self.lanes
        nbx = -(-w // lanes)
        gstride, gh = nbx * lanes + 2 * lanes, h + 2
        cells = gstride * gh
        inkmap = self._buffer("inkmap", cells * 4)
        maps = cells * 4 if has_input else 4  # end points: only over an input
        sxmap, symap = self._buffer("sxmap", maps), self._buffer("symap", maps)
        listing = self._buffer("list", w * h * 4)
        counter = self._buffer("count", 4)
        zero = np.zeros(1, np.int32)
        cl.enqueue_copy(queue, counter, zero, is_blocking=False)
        centres = kernels["marble_centres"]
        centres.set_args(
            inkmap,
            sxmap,
            symap,
            np.int32(gstride),
            np.int32(gh),
            pbuf,
            *_maps(geo),
        )
        rows, chains = layout  # the program's
        self._launch(centres, gstride // lanes * -(-gh // chains))
        classify = kernels["marble_classify"]
        classify.set_args(
            dst,
            np.int32(w),
            np.int32(h),
            inkmap,
            sxmap,
            symap,
            np.int32(gstride),
            listing,
            counter,
            *common,
        )
        group = self._classify_group
        cl.enqueue_nd_range_kernel(queue, classify, (_pad(nbx * h, group),), (group,))
        count = np.empty(1, np.int32)
        cl.enqueue_copy(queue, count, counter, is_blocking=True)
        n = int(count[0])
        self.last_full_pixels = n
        if n:
            full = kernels["marble_list"]
            full.set_args(dst, np.int32(w), listing, np.int32(n), *common)
            self._launch(full, -(-n // (lanes * rows)))
