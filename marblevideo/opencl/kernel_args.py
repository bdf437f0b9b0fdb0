"""Every kernel's arguments by name: one table, in the order the kernels declare them.

Callers set a kernel's arguments by name with :func:`set_args` (shared values in
a mapping, such as :func:`walk_args`' ``KPARAMS`` values, and the kernel's own by
keyword), never by position, so a kernel whose arguments are reordered or
renamed in kernels/ fails at its first launch with the names that are missing,
instead of running with its arguments swapped. tests/test_kernel_args.py builds
the program with ``-cl-kernel-arg-info`` and checks this table against the
names the device reports (:func:`declared_args`).
"""

from __future__ import annotations

from collections.abc import Mapping

#: What every marbling kernel ends with (``KPARAMS`` in kernels/walk.cl): the
#: padded input, its size, the packed params, the pattern's samples, the
#: geometry's two float4s, the background colour, the ops' lists.
KPARAMS = ("src", "sw", "sh", "params", "samples", "gc", "gi", "bgc", "lists")
#: A walked lattice (``LATTICE_ARGS`` in kernels/lattice.cl).
LATTICE_ARGS = ("state", "lx", "ly", "lstride", "ncx", "ncy", "lat")
#: An output plane's head: the I420 buffer, the plane's offsets, size, input
#: quads and whether it is chroma (kernels/planar.cl).
PLANE_HEAD = ("dst", "off0", "off1", "w", "h", "q0", "q1", "chroma")
#: The adaptive walk's per-pixel maps (kernels/adaptive.cl).
CENTRE_MAPS = ("inkmap", "sxmap", "symap", "gstride")

#: kernel name -> its argument names, in declaration order
KERNEL_ARGS: dict[str, tuple[str, ...]] = {
    "marble_pad": ("src", "sw", "sh", "bg"),
    "marble": ("dst", "w", "h", *KPARAMS),
    "marble_centres": (*CENTRE_MAPS, "gh", "params", "gc", "gi", "lists"),
    "marble_classify": ("dst", "w", "h", *CENTRE_MAPS, "list", "count", *KPARAMS),
    "marble_list": ("dst", "w", "list", "count", *KPARAMS),
    "marble_table": ("taps", "wts", "w", "h", "tstride", *KPARAMS),
    "marble_apply": ("dst", "w", "h", "taps", "wts", "tstride", "src", "sw", "samples"),
    "marble_from_i420": ("dst", "off", "stride", "yuv", "w", "h", "m"),
    "marble_to_i420": ("yuv", "src", "w", "h", "m"),
    "marble_quads": ("quads", "yuv", "off", "pw", "ph", "bg"),
    "marble_plane": (*PLANE_HEAD, *KPARAMS),
    "marble_apply_plane": (*PLANE_HEAD, "taps", "wts", "tstride", "samples"),
    "marble_lattice_cells": ("state", *CENTRE_MAPS, "ncx", "ncy", "gi", "tol", "reach", "rules"),
    "marble_lattice": ("dst", "w", "h", *LATTICE_ARGS, *KPARAMS),
    "marble_lattice_plane": (*PLANE_HEAD, *LATTICE_ARGS, *KPARAMS),
}


def walk_args(src, sw, sh, params, samples, maps, bgc, lists) -> dict:
    """The ``KPARAMS`` values of a walk by name; ``maps``: the geometry's
    (gc, gi) float4 pair."""
    gc, gi = maps
    return dict(
        src=src, sw=sw, sh=sh, params=params, samples=samples, gc=gc, gi=gi, bgc=bgc, lists=lists
    )


def set_args(kernel, shared: Mapping | None = None, **values) -> None:
    """Set ``kernel``'s arguments by name: each from ``values``, else from
    ``shared`` (whose other entries are left alone). A name the kernel does not
    take in ``values``, or one of its arguments given nowhere, is a TypeError
    naming the kernel."""
    shared = shared or {}
    name = kernel.function_name
    names = KERNEL_ARGS[name]
    unknown = sorted(set(values) - set(names))
    missing = [n for n in names if n not in values and n not in shared]
    if unknown or missing:
        raise TypeError(f"kernel {name}: unknown arguments {unknown}, missing {missing}")
    kernel.set_args(*(values[n] if n in values else shared[n] for n in names))


def declared_args(program) -> dict[str, tuple[str, ...]]:
    """Each kernel of ``program`` (built with ``-cl-kernel-arg-info``) and its
    argument names as the device reports them."""
    import pyopencl as cl

    return {
        k.function_name: tuple(
            k.get_arg_info(i, cl.kernel_arg_info.NAME) for i in range(k.num_args)
        )
        for k in program.all_kernels()
    }
