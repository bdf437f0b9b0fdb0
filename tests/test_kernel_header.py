"""The kernels' generated header (marblevideo/opencl/header.py) agrees with the
Python definitions: a kernel built from the header reads every op's packed
floats back through their named offsets (P_<TYPE>_<SLOT>) and finds what each
op's packer wrote under those names, the type codes and colours where the walk
reads them; and the op sections read their parameters only by name."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from marblevideo.opencl.header import (
    STILL_CODE,
    code_macro,
    edges_macro,
    header_source,
    slot_macro,
)
from marblevideo.opencl.program import pack_params
from marblevideo.ops import COLOR_SLOTS, PSTRIDE, REGISTRY, op_def
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import EDGE_MODES

pytestmark = pytest.mark.tier("fast")

ROOT = Path(__file__).resolve().parent.parent
OPS = list(REGISTRY.values())

READ_BACK = """
__kernel void read_back(__constant const float *params, __global float *floats,
                        __global int *ints) {
%s
}
"""


def every_example():
    """A frame of every op's example, in registry order, at its end."""
    doc = {"canvas": [80, 60], "ops": [dict(d.example) for d in OPS]}
    recipe = parse_recipe(doc, "ex.json")
    return recipe.at(recipe.end_time())


def run_read_back(renderer, params: np.ndarray, float_reads: list[str], int_reads: list[str]):
    """The floats and ints that the expressions read, in a kernel built from the header."""
    import pyopencl as cl

    body = [f"    floats[{k}] = {e};" for k, e in enumerate(float_reads)]
    body += [f"    ints[{k}] = {e};" for k, e in enumerate(int_reads)]
    program = renderer.build_program(header_source() + READ_BACK % "\n".join(body), [])
    ctx, queue = renderer.context, renderer.device_queue.queue
    mf = cl.mem_flags
    pbuf = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=params)
    floats, ints = np.empty(len(float_reads), np.float32), np.empty(len(int_reads), np.int32)
    fbuf, ibuf = (cl.Buffer(ctx, mf.WRITE_ONLY, a.nbytes + 4) for a in (floats, ints))
    kernel = cl.Kernel(program, "read_back")
    kernel.set_args(pbuf, fbuf, ibuf)
    cl.enqueue_nd_range_kernel(queue, kernel, (1,), None)
    cl.enqueue_copy(queue, floats, fbuf)
    cl.enqueue_copy(queue, ints, ibuf)
    queue.finish()
    return floats, ints


def test_the_header_reads_back_what_every_packer_wrote(renderer):
    spec = every_example()
    packed = pack_params(spec)
    lists: list[float] = [float(len(spec.ops))]  # as pack_params fills it
    reads, expected = [], []
    for i, op in enumerate(spec.ops):
        definition = op_def(op.type)
        named = definition.pack(op.values, lists)  # by name, as the packer wrote it
        for slot in definition.slots:
            reads.append(f"params[{i} * PSTRIDE + {slot_macro(op.type, slot)}]")
            expected.append(named[slot])
        if definition.ink:
            reads += [f"params[{i} * PSTRIDE + COLOR_SLOT + {k}]" for k in range(3)]
            expected += list(op["color"])
    codes = [f"(int)params[{i} * PSTRIDE + CODE_SLOT]" for i in range(len(spec.ops))]
    floats, ints = run_read_back(renderer, packed.params, reads, codes)
    np.testing.assert_array_equal(floats, np.float32(expected))
    assert ints.tolist() == [op_def(op.type).code for op in spec.ops]
    assert np.array_equal(packed.lists, np.float32(lists))


def test_the_header_carries_the_python_constants(renderer):
    names = {code_macro(d.type): d.code for d in OPS}
    names |= {edges_macro(mode): k for k, mode in enumerate(EDGE_MODES)}
    names |= {"PSTRIDE": PSTRIDE, "CODE_SLOT": PSTRIDE - 1, "COLOR_SLOT": COLOR_SLOTS[0]}
    names |= {"CODE_STILL": STILL_CODE}
    _, ints = run_read_back(renderer, np.zeros(PSTRIDE, np.float32), [], list(names))
    assert dict(zip(names, ints.tolist(), strict=True)) == names


def test_op_sections_read_their_parameters_by_name():
    for path in sorted((ROOT / "kernels" / "ops").glob("*.cl")):
        text = path.read_text()
        assert not re.search(r"\bp\[\s*\d", text), f"{path.name} reads p[] by position"
        used = {m for m in re.findall(r"\bP_[A-Z0-9_]+", text) if not m.endswith("_")}
        defined = set(re.findall(r"#define (P_\w+)", header_source()))
        assert used <= defined, used - defined


def test_every_kernel_file_is_in_the_program_and_small():
    """Each .cl file is joined into the renderer's program (prelude, op sections,
    KERNEL_FILES) or an exported one (EXPORT_FILES), and holds one concern in at
    most 400 lines."""
    from marblevideo.export.opencl import EXPORT_FILES
    from marblevideo.opencl.program import KERNEL_FILES

    families = {d.family for d in OPS}
    joined = {
        "prelude.cl",
        "math.cl",
        *(f"ops/{f}.cl" for f in families),
        *KERNEL_FILES,
        *EXPORT_FILES,
    }
    files = {
        p.relative_to(ROOT / "kernels").as_posix(): p for p in (ROOT / "kernels").rglob("*.cl")
    }
    assert set(files) == joined
    for name, path in files.items():
        assert len(path.read_text().splitlines()) <= 400, name
