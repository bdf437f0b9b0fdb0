"""Kernel arguments by name: the table in marblevideo.opencl.kernel_args against
the names the device reports for a program built with ``-cl-kernel-arg-info``,
for every kernel of the program (a blank sheet and an input, RGSS and none)."""

from __future__ import annotations

import numpy as np
import pytest

from marblevideo.opencl.kernel_args import KERNEL_ARGS, declared_args, set_args
from marblevideo.opencl.program import Structure

pytestmark = pytest.mark.tier("fast")

ARG_INFO = "-cl-kernel-arg-info"
STRUCTURES = (
    Structure(("drop", "comb", "wave"), "rgss", "mirror", True),
    Structure(("drop",), "none", "repeat", False),
)


def built_with_arg_info(renderer, structure: Structure, source: str | None = None):
    """``structure``'s program (or ``source`` with its options) built with argument info."""
    programs = renderer.programs
    options, _, _ = programs.options(structure)
    source = source or programs.full_source(structure)
    return renderer.build_program(source, [*options, ARG_INFO])


@pytest.mark.parametrize("structure", STRUCTURES, ids=lambda s: f"{s.antialias}-{s.has_input}")
def test_the_table_names_every_kernel_argument_in_the_order_declared(renderer, structure):
    assert declared_args(built_with_arg_info(renderer, structure)) == KERNEL_ARGS


def test_an_argument_order_changed_in_the_source_is_caught(renderer):
    """The check above fails when a kernel's arguments move and the table does not."""
    structure = STRUCTURES[0]
    source = renderer.programs.full_source(structure)
    signature = "marble_pad(__global uint *src, int sw, int sh, uint bg)"
    assert signature in source
    swapped = source.replace(signature, "marble_pad(__global uint *src, int sh, int sw, uint bg)")
    declared = declared_args(built_with_arg_info(renderer, structure, swapped))
    assert declared["marble_pad"] == ("src", "sh", "sw", "bg") != KERNEL_ARGS["marble_pad"]
    assert {k: v for k, v in declared.items() if k != "marble_pad"} == {
        k: v for k, v in KERNEL_ARGS.items() if k != "marble_pad"
    }


def test_set_args_refuses_a_missing_or_unknown_name(renderer):
    kernel = renderer.kernel_for(STRUCTURES[0]).kernels["marble_pad"]
    buf = renderer.device_queue.buffer("padded", 64)
    values = dict(src=buf, sw=np.int32(2), sh=np.int32(2))
    with pytest.raises(TypeError, match=r"marble_pad: unknown arguments \[\], missing \['bg'\]"):
        set_args(kernel, values)
    with pytest.raises(TypeError, match=r"unknown arguments \['colour'\]"):
        set_args(kernel, values, bg=np.uint32(0), colour=np.uint32(0))
    set_args(kernel, values, bg=np.uint32(0))  # all four, by name
