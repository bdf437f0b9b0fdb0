"""The program: one OpenCL program per recipe *structure*, built from kernels/.

A recipe's structure (op types in order, antialiasing pattern, edges mode,
blank sheet or input) is built into a program once; the per-frame values (a
:class:`~marblevideo.recipe.frame.FrameSpec`) are packed into a small float
buffer by :func:`pack_params`, so animating a recipe never recompiles.
:class:`Programs` caches each structure's kernels, fetched once.

The source is kernels/prelude.cl, kernels/math.cl, each op family's sections
(kernels/ops/<family>.cl) and the files of :data:`KERNEL_FILES` (edges, sampling, the
walk, adaptive antialiasing, tables, I420, planes, the lattice), after a header
generated from the op definitions (:mod:`marblevideo.opencl.header`: parameter
offsets, type codes, edges modes, the walk). Every kernel in the source is
fetched once, by its name. On CPU devices the kernels run vector code as wide
as the device's native float vectors (:func:`cpu_lanes`: 16 lanes on AVX-512, 8
on AVX2, 4 on SSE) with several independent chains per work-item
(:func:`cpu_chains`; see BENCHMARKS.md); on GPUs one pixel per work-item.

Programs build silently: the OpenCL compiler's warnings are switched off
(``-w``) and its log is kept, unless the ``marblevideo`` logger is enabled for
DEBUG (the CLI's ``--verbose``), which builds with warnings and logs the build
log; a failed build raises a one-line DeviceError naming a file that holds the
whole log. A silent build is kept as the device's binary between processes
(:mod:`marblevideo.opencl.binaries`): the next process that needs it starts sooner.
"""

from __future__ import annotations

import logging
import os
import tempfile
import threading
import time
import warnings
from contextlib import suppress
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

import numpy as np

from marblevideo.errors import DeviceError, UsageError
from marblevideo.opencl.binaries import binary_key, load_binary, store_binary
from marblevideo.opencl.device import DeviceInfo
from marblevideo.opencl.header import STILL_CODE, edges_macro, header_source, walk_source
from marblevideo.ops import PSTRIDE, REGISTRY, op_def
from marblevideo.ops.ink import link_concentric_drops
from marblevideo.recipe.antialias import pattern
from marblevideo.recipe.frame import FrameSpec

#: Recipes longer than this walk their ops in a loop instead of unrolled code.
UNROLL_LIMIT = 48
#: Pixels whose walks a CPU work-item keeps in flight (lanes x chains): 4 chains
#: of 16 lanes with AVX-512; with 8 lanes, 8 chains did as well as 16 lanes
#: (BENCHMARKS.md, vector width).
CPU_PIXELS_IN_FLIGHT = 64
#: Environment variable that overrides the vector width on CPU devices (4, 8 or 16).
LANES_VARIABLE = "MARBLEVIDEO_LANES"
#: Vector widths the kernel is written for.
VECTOR_WIDTHS = (4, 8, 16)
#: The kernels' files after the prelude and the op sections, in the order they are
#: joined (each uses only what the files before it define).
KERNEL_FILES = (
    "edges.cl",
    "sampling.cl",
    "walk.cl",
    "adaptive.cl",
    "tables.cl",
    "i420.cl",
    "planar.cl",
    "lattice.cl",
)

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


def kernel_source(name: str = "walk.cl") -> str:
    """An OpenCL source (a path under kernels/) from the installed package, or from
    the repository's kernels/."""
    packaged = resources.files("marblevideo") / "kernels" / name
    if packaged.is_file():
        return packaged.read_text()
    return (Path(__file__).resolve().parents[2] / "kernels" / name).read_text()


def program_source() -> str:
    """The program's source without its generated header: the prelude, the math
    helpers, each op family's sections (kernels/ops/<family>.cl, in registry order) and
    :data:`KERNEL_FILES`."""
    families = dict.fromkeys(d.family for d in REGISTRY.values())
    parts = ["prelude.cl", "math.cl", *(f"ops/{family}.cl" for family in families), *KERNEL_FILES]
    return "\n".join(kernel_source(name) for name in parts)


@dataclass(frozen=True)
class Packed:
    """A frame's op values for the kernel: ``params``, PSTRIDE float32 per op, and
    ``lists``, the float32 variable-length data the ops index into, after the
    number of ops (so never empty)."""

    params: np.ndarray
    lists: np.ndarray

    @property
    def key(self) -> bytes:
        """The bytes that decide where every subsample lands (for reused maps)."""
        return self.params.tobytes() + b"|" + self.lists.tobytes()


def pack_params(spec: FrameSpec) -> Packed:
    """Per-frame op values: each op's definition packs its floats
    (:attr:`marblevideo.ops.OpDef.pack`; no library trigonometry is left for the
    kernel), the last float of its row is its type code, or STILL_CODE for an
    op that moves nothing and holds no ink this frame (one not started yet).
    ``lists`` begins with the number of ops (the loop walk's count; see
    :func:`walk_source`)."""
    out = np.zeros((max(len(spec.ops), 1), PSTRIDE), dtype=np.float64)
    lists: list[float] = [float(len(spec.ops))]
    walked = []
    for i, op in enumerate(spec.ops):
        definition = op_def(op.type)
        row = definition.packed(op.values, lists)
        out[i, : len(row)] = row
        if definition.still(op.values):
            out[i, PSTRIDE - 1] = STILL_CODE
        else:
            out[i, PSTRIDE - 1] = definition.code
            walked.append(i)
    link_concentric_drops(spec.ops, out, walked)
    # Products of valid values (radius**2, alpha * lambda) can pass float32's range:
    # saturate them rather than hand the kernel inf (and inf * 0 = NaN).
    f32 = float(np.finfo(np.float32).max)
    params = np.clip(out, -f32, f32).astype(np.float32).ravel()
    data = np.clip(np.array(lists, np.float64), -f32, f32).astype(np.float32)
    return Packed(params, data)


@dataclass(frozen=True)
class Structure:
    """What a program is built for; everything else is a per-frame value."""

    types: tuple[str, ...] | None  # None: any (the loop walk's programs)
    antialias: str
    edges: str
    has_input: bool

    @classmethod
    def of(cls, spec, has_input: bool) -> Structure:
        """The structure of a FrameSpec or a Recipe (both have ops with a type,
        antialias and edges)."""
        return cls(tuple(op.type for op in spec.ops), spec.antialias, spec.edges, has_input)


@dataclass(frozen=True)
class Built:
    """A structure's program: its kernels by name, and the layout it was built for
    (output rows and independent chains per work-item)."""

    kernels: dict
    rows: int
    chains: int


class Programs:
    """The programs of one device: its vector width (``lanes``; ``yuv_lanes`` for
    the I420 and quad kernels) and chains, each structure's program built once
    (one build at a time) and cached. ``source`` is the program's source
    without its generated header. ``loop``: every recipe through the loop walk's
    one program (no build when a recipe's ops change, as in the designer)."""

    def __init__(
        self,
        context,
        info: DeviceInfo,
        lanes: int | None,
        chains: int | None,
        loop: bool = False,
    ):
        import pyopencl as cl

        self._cl, self.context, self.info = cl, context, info
        dev = info.device
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
            info.label,
            info.name,
            info.platform,
            self.lanes,
            "s" * (self.lanes != 1),
            self.chains,
            "s" * (self.chains != 1),
            native,
        )
        self.source = program_source()
        self.loop = loop
        self._built: dict[Structure, Built] = {}
        self._lock = threading.Lock()

    @property
    def built(self) -> int:
        """How many programs have been built."""
        return len(self._built)

    def layout(self, nsamples: int) -> tuple[int, int]:
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
                self.get(structure)

        threading.Thread(target=build, name="marblevideo-build").start()

    def program_key(self, structure: Structure) -> Structure:
        """The structure a program is built for: ``structure``, or, for the loop
        walk (above UNROLL_LIMIT ops, or every recipe when ``loop``), the same
        without its op types (types None), one program for every such recipe."""
        if self.loop or len(structure.types) > UNROLL_LIMIT:
            return replace(structure, types=None)
        return structure

    def get(self, structure: Structure) -> Built:
        """The program of ``structure``, built on first use and cached (one build at
        a time: a caller waits for a :meth:`prebuild` of the same program)."""
        structure = self.program_key(structure)
        built = self._built.get(structure)
        if built is not None:
            return built
        with self._lock:
            built = self._built.get(structure)
            return built if built is not None else self.build(structure)

    def options(self, structure: Structure) -> tuple[list[str], int, int]:
        """(build options, rows, chains) of ``structure``'s program."""
        nsamples = len(pattern(structure.antialias))
        rows, chains = self.layout(nsamples)
        options = [
            f"-DLANES={self.lanes}",
            f"-DCHAINS={chains}",
            f"-DROWS={rows}",
            f"-DNSAMPLES={nsamples}",
            f"-DHAS_INPUT={int(structure.has_input)}",
            f"-DEDGES={edges_macro(structure.edges)}",
            f"-DYLANES={self.yuv_lanes}",
        ]
        return options, rows, chains

    def full_source(self, structure: Structure) -> str:
        """``structure``'s whole source: the generated header and walk, then :attr:`source`."""
        return header_source() + walk_source(structure.types) + self.source

    def build(self, structure: Structure) -> Built:
        """Build and cache ``structure``'s program (the caller holds the lock)."""
        options, rows, chains = self.options(structure)
        program = self.build_program(self.full_source(structure), options)
        kernels = {k.function_name: k for k in program.all_kernels()}
        built = self._built[structure] = Built(kernels, rows, chains)
        return built

    def build_program(self, source: str, options: list[str]):
        """A program of ``source`` built for this renderer's device with ``options``:
        silently (``-w``; pyopencl's CompilerWarning dropped) unless the
        ``marblevideo`` logger is enabled for DEBUG, which gets the build log. A
        silent build starts from the binary of an earlier one of the same source,
        options and device where one is kept (:mod:`~marblevideo.opencl.binaries`).
        A failed build raises DeviceError in one line (see the module)."""
        cl = self._cl
        verbose = log.isEnabledFor(logging.DEBUG)
        if not verbose:
            options = [*options, "-w"]
            key = binary_key(self.info.device, source, options)
            program = self._from_binary(key, options)
            if program is not None:
                return program
        began = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", cl.CompilerWarning)
                program = cl.Program(self.context, source).build(options=options)
        except cl.Error as exc:
            raise DeviceError(self._build_failure(str(exc), source, options)) from None
        if not verbose:
            store_binary(key, program.get_info(cl.program_info.BINARIES)[0])
        else:
            text = program.get_build_info(self.info.device, cl.program_build_info.LOG)
            log.debug(
                "built the kernels for %s in %.2f s (%s)%s",
                self.info.name,
                time.perf_counter() - began,
                " ".join(options),
                f"; build log:\n{text.strip()}" if text.strip() else "; empty build log",
            )
        return program

    def _from_binary(self, key: str, options: list[str]):
        """The program kept under ``key`` (:mod:`~marblevideo.opencl.binaries`), built
        from its binary; None when none is kept or the driver refuses it."""
        binary = load_binary(key)
        if binary is None:
            return None
        cl = self._cl
        try:
            return cl.Program(self.context, [self.info.device], [binary]).build(options=options)
        except cl.Error:
            return None

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
