"""Exports: a recipe written as a program that another host runs on its own GPU.

- ``.cl``: one self-contained OpenCL C file for ffmpeg's ``program_opencl``
  filter and ``openclsrc`` source (:mod:`.opencl`);
- ``.frag``: a GLSL 3.30 fragment shader for GStreamer's ``glshader``, its vertex
  shader beside as ``.vert``; ``.fs``: an ISF 2.0 file (:mod:`.shader`), filters
  or, with ``sheet``, generators; ``--to shadertoy``: Shadertoy's Image tab.

All are built from the renderer's own op sections (kernels/ops/; GLSL through
:mod:`.dialect`) and the frames' packed values (:mod:`.frames`).

Generated code never holds a recipe's text: only validated numbers, written as
float literals that read back to the same float32, and the kernels' own source.
"""

from __future__ import annotations

from pathlib import Path

from marblevideo.errors import UsageError

#: Output formats by extension, and by ``--to`` name.
FORMATS = {".cl": "ffmpeg", ".frag": "gstreamer", ".fs": "isf"}
#: Formats named by ``--to`` only (any extension).
TO_ONLY = ("shadertoy",)


def format_of(output: str, to: str | None) -> str:
    """The format of ``output``: ``to`` when given, else by its extension."""
    if to is not None:
        if to not in (*FORMATS.values(), *TO_ONLY):
            names = ", ".join((*FORMATS.values(), *TO_ONLY))
            raise UsageError(f"--to: expected one of {names}")
        return to
    suffix = Path(output).suffix.lower()
    if suffix not in FORMATS:
        known = ", ".join(f"{ext} ({name})" for ext, name in FORMATS.items())
        raise UsageError(
            f"{output}: unknown export extension {suffix or '(none)'!r}; expected {known}, "
            "or --to shadertoy"
        )
    return FORMATS[suffix]


def export_source(
    recipe, fmt: str, fps: float, constant_bytes: int | None = None, sheet: bool = False
) -> str:
    """``recipe`` (validated) as the source of format ``fmt``: frames at ``fps``,
    tables within ``constant_bytes`` (.cl; default EXPORT_CONSTANT_BYTES), a
    generator with ``sheet`` (.frag, .fs: the .cl file has both kernels)."""
    from marblevideo.export.opencl import opencl_program
    from marblevideo.export.shader import gstreamer_shader, isf_shader, shadertoy_shader
    from marblevideo.limits import EXPORT_CONSTANT_BYTES, EXPORT_MAX_CONSTANT_BYTES

    limit = EXPORT_CONSTANT_BYTES if constant_bytes is None else constant_bytes
    if not EXPORT_CONSTANT_BYTES <= limit <= EXPORT_MAX_CONSTANT_BYTES:
        raise UsageError(
            f"--constant-memory: expected {EXPORT_CONSTANT_BYTES} to "
            f"{EXPORT_MAX_CONSTANT_BYTES} bytes, got {limit}"
        )
    if fmt == "ffmpeg":
        return opencl_program(recipe, fps, limit)
    if constant_bytes is not None:
        raise UsageError("--constant-memory: only for .cl (a shader's data is its own)")
    if fmt == "gstreamer":
        return gstreamer_shader(recipe, fps, sheet)
    if fmt == "isf":
        return isf_shader(recipe, fps, sheet)
    if fmt == "shadertoy":
        return shadertoy_shader(recipe, fps, sheet)
    raise UsageError(f"unknown export format {fmt!r}")
