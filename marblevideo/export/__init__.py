"""Exports: a recipe written as a program that another host runs on its own GPU.

``.cl``: one self-contained OpenCL C file for ffmpeg's ``program_opencl`` filter
and ``openclsrc`` source (:mod:`.opencl`), built from the renderer's own op
sections (kernels/ops/) and the frames' packed values (:mod:`.frames`).

Generated code never holds a recipe's text: only validated numbers, written as
float literals that read back to the same float32, and the kernels' own source.
"""

from __future__ import annotations

from pathlib import Path

from marblevideo.errors import UsageError

#: Output formats by extension, and by ``--to`` name.
FORMATS = {".cl": "ffmpeg"}


def format_of(output: str, to: str | None) -> str:
    """The format of ``output``: ``to`` when given, else by its extension."""
    if to is not None:
        if to not in FORMATS.values():
            raise UsageError(f"--to: expected one of {', '.join(sorted(set(FORMATS.values())))}")
        return to
    suffix = Path(output).suffix.lower()
    if suffix not in FORMATS:
        known = ", ".join(f"{ext} ({name})" for ext, name in FORMATS.items())
        raise UsageError(
            f"{output}: unknown export extension {suffix or '(none)'!r}; expected {known}"
        )
    return FORMATS[suffix]


def export_source(recipe, fmt: str, fps: float, constant_bytes: int | None = None) -> str:
    """``recipe`` (validated) as the source of format ``fmt``: frames at ``fps``
    (.cl), tables within ``constant_bytes`` (default EXPORT_CONSTANT_BYTES)."""
    from marblevideo.export.opencl import opencl_program
    from marblevideo.limits import EXPORT_CONSTANT_BYTES, EXPORT_MAX_CONSTANT_BYTES

    limit = EXPORT_CONSTANT_BYTES if constant_bytes is None else constant_bytes
    if not EXPORT_CONSTANT_BYTES <= limit <= EXPORT_MAX_CONSTANT_BYTES:
        raise UsageError(
            f"--constant-memory: expected {EXPORT_CONSTANT_BYTES} to "
            f"{EXPORT_MAX_CONSTANT_BYTES} bytes, got {limit}"
        )
    if fmt == "ffmpeg":
        return opencl_program(recipe, fps, limit)
    raise UsageError(f"unknown export format {fmt!r}")
