"""A recipe as one OpenCL C file for ffmpeg: ``program_opencl`` (kernel
``marble``, over the input frames) and ``openclsrc`` (kernel ``marble_sheet``, a
blank sheet); frame ``index`` is the recipe at ``index / fps``.

The file is the renderer's program for one pixel per work-item: the generated
header and walk (:mod:`marblevideo.opencl.header`), kernels/prelude.cl, the op
sections (kernels/ops/), kernels/edges.cl and kernels/export/ffmpeg.cl, after
the build-time defines ffmpeg cannot pass and the frames' data
(:mod:`.frames`) as program-scope constants. Nothing of the recipe's text is
written: only its numbers.
"""

from __future__ import annotations

from marblevideo.export.frames import check_exportable, frame_table
from marblevideo.export.source import literal, one_pixel_defines, walk_types
from marblevideo.limits import EXPORT_CONSTANT_BYTES
from marblevideo.opencl.header import edges_macro, header_source, walk_source
from marblevideo.opencl.program import kernel_source
from marblevideo.ops import REGISTRY
from marblevideo.version import __version__

#: The kernels' files of the exported program, after the op sections.
EXPORT_FILES = ("edges.cl", "export/ffmpeg.cl")
#: Floats a line of the data tables.
_PER_LINE = 8

_USAGE = """\
/* marblevideo {version}: a marbling recipe as an OpenCL program for ffmpeg.
 * Frame `index` shows the recipe at index / {fps:g} s (exported with --fps {fps:g};
 * {frames} frame{s} until it settles; the last holds from then on).
 *
 * Over a video (the program_opencl filter, kernel `marble`):
 *   ffmpeg -init_hw_device opencl=ocl -filter_hw_device ocl -i in.mp4 \\
 *     -vf "format=rgba,hwupload,program_opencl=source=FILE.cl:kernel=marble,\\
 *     hwdownload,format=rgba,format=yuv420p" -c:a copy out.mp4
 * On a blank sheet (the openclsrc source, kernel `marble_sheet`):
 *   ffmpeg -init_hw_device opencl=ocl -filter_hw_device ocl -filter_complex \\
 *     "openclsrc=source=FILE.cl:kernel=marble_sheet:size=1280x720:format=rgba:\
rate={fps:g},\\
 *     hwdownload,format=rgba,format=yuv420p" -frames:v {frames} sheet.mp4
 * (a line ending in a backslash inside the quotes goes on without a break; on one
 * line, drop the backslashes). -init_hw_device opencl=ocl:P.D picks platform P,
 * device D.
 */
"""


def _table(ctype: str, name: str, values, write) -> str:
    """A program-scope constant array of ``values``, each written by ``write``."""
    items = [write(v) for v in values]
    lines = [", ".join(items[k : k + _PER_LINE]) for k in range(0, len(items), _PER_LINE)]
    body = ",\n    ".join(lines)
    return f"__constant {ctype} {name}[{len(items)}] = {{\n    {body}\n}};\n"


def opencl_program(recipe, fps: float, constant_bytes: int = EXPORT_CONSTANT_BYTES) -> str:
    """The ``.cl`` file of ``recipe`` (validated) with frames at ``fps``, its tables
    within ``constant_bytes``."""
    check_exportable(recipe, "a .cl export")
    canvas = recipe.canvas or (1.0, 1.0)
    table = frame_table(recipe, fps, canvas, constant_bytes)
    defines = [*one_pixel_defines(recipe, table), "#define LIST_SPACE __constant"]
    families = dict.fromkeys(d.family for d in REGISTRY.values())
    header = header_source() + f"#define EDGES {edges_macro(recipe.edges)}\n"
    parts = [
        _USAGE.format(
            version=__version__, fps=fps, frames=table.frames, s="s" * (table.frames != 1)
        ),
        "\n".join(defines) + "\n",
        header + walk_source(walk_types(recipe)),
        _table("float", "MV_ROWS", table.rows.ravel(), literal),
        _table("int", "MV_ROW_AT", table.row_at, str),
        _table("int", "MV_FIRST", table.first, str),
        _table("int", "MV_COUNT", table.count, str),
        _table("float", "MV_LISTS", table.lists, literal),
        _table("float", "MV_BACKGROUND", table.background.ravel(), literal),
        _table("float", "MV_SAMPLES", table.samples.ravel(), literal),
        kernel_source("prelude.cl"),
        kernel_source("math.cl"),
        *(kernel_source(f"ops/{family}.cl") for family in families),
        *(kernel_source(name) for name in EXPORT_FILES),
    ]
    return "\n".join(parts)
