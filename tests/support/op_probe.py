"""Run one op's kernel section on chosen points: the real OpenCL code of
kernels/ops/<family>.cl, built with the prelude into a small probe program (a
chained section, :attr:`marblevideo.ops.OpDef.chained`, on ``chains`` vectors
of consecutive points per work-item)."""

from __future__ import annotations

import numpy as np

from marblevideo.opencl.header import header_source
from marblevideo.opencl.program import kernel_source, pack_params
from marblevideo.ops import op_def
from marblevideo.recipe.frame import FrameSpec, OpState

PROBE = """
__kernel void probe(__global const float *xs, __global const float *ys, __global float *ox,
                    __global float *oy, __global int *oink, __constant const float *params,
                    __global const float *lists) {
    const int at = get_global_id(0) * LANES * CHAINS;
    vf x[CHAINS], y[CHAINS];
    vi ink[CHAINS];
    for (int c = 0; c < CHAINS; c++) {
        x[c] = VLOAD(xs + at + c * LANES);
        y[c] = VLOAD(ys + at + c * LANES);
        ink[c] = (vi)-1;
    }
#if PROBE_CHAINED
    PROBE_OP(x, y, ink, params, 0, lists);
#else
    for (int c = 0; c < CHAINS; c++)
        PROBE_OP(&x[c], &y[c], &ink[c], params, 0, lists);
#endif
    for (int c = 0; c < CHAINS; c++) {
        VSTORE(x[c], ox + at + c * LANES);
        VSTORE(y[c], oy + at + c * LANES);
        VSTORE(ink[c], oink + at + c * LANES);
    }
}
"""


def run_op(
    renderer, op: OpState, x: np.ndarray, y: np.ndarray, lanes: int | None = None, chains: int = 1
):
    """(x, y, ink) of the points (float32) walked back through ``op`` by its kernel
    section on ``renderer``'s device, ``lanes`` wide (default: the renderer's), in
    work-items of ``chains`` vectors (consecutive points)."""
    import pyopencl as cl

    definition = op_def(op.type)
    lanes = lanes or renderer.lanes
    spec = FrameSpec((op,), (0.0, 0.0, 0.0), "none", "clamp", (1.0, 1.0))
    packed = pack_params(spec)
    source = header_source() + kernel_source("prelude.cl") + kernel_source("math.cl")
    source += kernel_source(f"ops/{definition.family}.cl") + PROBE
    options = [
        f"-DLANES={lanes}",
        f"-DCHAINS={chains}",
        "-DROWS=1",
        "-DNSAMPLES=1",
        f"-DPROBE_OP={definition.kernel_function}",
        f"-DPROBE_CHAINED={int(definition.chained)}",
    ]
    program = renderer.build_program(source, options)
    n = -(-x.size // (lanes * chains)) * lanes * chains
    xs = np.zeros(n, np.float32)
    ys = np.zeros(n, np.float32)
    xs[: x.size], ys[: y.size] = x.ravel(), y.ravel()
    ctx, queue = renderer.context, renderer.device_queue.queue
    mf = cl.mem_flags
    bufs = [cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=a) for a in (xs, ys)]
    outs = [np.empty(n, np.float32), np.empty(n, np.float32), np.empty(n, np.int32)]
    out_bufs = [cl.Buffer(ctx, mf.WRITE_ONLY, a.nbytes) for a in outs]
    pbuf = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=packed.params)
    lbuf = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=packed.lists)
    kernel = cl.Kernel(program, "probe")
    kernel.set_args(*bufs, *out_bufs, pbuf, lbuf)
    cl.enqueue_nd_range_kernel(queue, kernel, (n // (lanes * chains),), None)
    for host, dev in zip(outs, out_bufs, strict=True):
        cl.enqueue_copy(queue, host, dev)
    queue.finish()
    return tuple(a[: x.size].reshape(x.shape) for a in outs)
