"""A device's command queue with its named buffers, and the copies to and from it.

Buffers are kept by name and grown, never shrunk, so a video reuses the same
device memory every frame. Copies from the host are queued without waiting;
their events hold the host arrays until copied (dropping one would wait for
it, and so for every frame queued before it). One in-order queue runs
everything, so frames in flight share the buffers safely.

A profiling queue (``profile=True``, off by default: each launch then keeps its
event) reports the device time of each kernel (:meth:`DeviceQueue.kernel_times`),
for the benchmarks (``python -m benchmarks kernels --profile``).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from marblevideo.errors import DeviceError
from marblevideo.opencl.device import DeviceInfo
from marblevideo.recipe.antialias import pattern

#: Work-group size of the kernels on CPU devices (GPUs choose their own).
CPU_GROUP = 128


def geometry_args(geom) -> tuple:
    """A render's :class:`~marblevideo.recipe.frame.Geometry` as the kernels' two
    float4 arguments (output -> canvas, canvas -> input; no wider vector: see
    kernels/prelude.cl), and its 8 float32s."""
    geo = np.array([*geom.to_canvas, *geom.to_input], dtype=np.float32)
    return (float4(geo[:4]), float4(geo[4:])), geo


def float4(values) -> object:
    """Four floats as an OpenCL float4 kernel argument."""
    import pyopencl.cltypes as cltypes

    return np.asarray(values, dtype=np.float32).view(cltypes.float4)[0]


def padded_size(n: int, multiple: int = 64) -> int:
    """Global sizes are padded to a multiple of 64 (PoCL picks a local size dividing it)."""
    return max(multiple, -(-n // multiple) * multiple)


class DeviceQueue:
    """The queue of ``context`` on the device ``info``; ``is_cpu`` sets the
    work-group size of :meth:`launch`; ``profile``: a profiling queue (see the
    module)."""

    def __init__(self, context, info: DeviceInfo, is_cpu: bool, profile: bool = False):
        import pyopencl as cl

        self._cl, self.context, self.info = cl, context, info
        properties = cl.command_queue_properties.PROFILING_ENABLE if profile else 0
        #: (kernel name, event) of each launch since the last kernel_times, when profiling
        self.launches: list[tuple[str, object]] | None = [] if profile else None
        try:
            self.queue = cl.CommandQueue(context, properties=properties)
        except cl.Error as exc:
            raise DeviceError(f"cannot open OpenCL device {info.name}: {exc}") from None
        #: work-group size on CPUs; PoCL's own choice made 15 groups of a 720p
        #: frame, which two cores shared unevenly (128 measured 5-10% faster)
        self.group = min(CPU_GROUP, info.device.max_work_group_size) if is_cpu else None
        self._buffers: dict[str, tuple[int, object]] = {}
        self._samples: dict[str, object] = {}

    def buffer(self, name: str, nbytes: int):
        """The buffer ``name``, at least ``nbytes`` long (DeviceError if it cannot be had)."""
        nbytes = max(int(nbytes), 4)
        have = self._buffers.get(name)
        if have is not None and have[0] >= nbytes:
            return have[1]
        try:
            buf = self._cl.Buffer(self.context, self._cl.mem_flags.READ_WRITE, nbytes)
        except self._cl.Error as exc:
            raise DeviceError(
                f"cannot allocate {nbytes} bytes on {self.info.name} ({exc}); try a smaller --size"
            ) from None
        self._buffers[name] = (nbytes, buf)
        return buf

    def samples(self, antialias: str):
        """The read-only buffer of an antialiasing pattern's (dx, dy, weight) rows."""
        buf = self._samples.get(antialias)
        if buf is None:
            data = pattern(antialias).astype(np.float32).ravel()
            mf = self._cl.mem_flags
            buf = self._cl.Buffer(self.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=data)
            self._samples[antialias] = buf
        return buf

    def launch(self, kernel, n: int, group: int | None = None) -> None:
        """Enqueue ``n`` work-items of ``kernel`` (padded; surplus items return at
        once) in work-groups of ``group`` items (default: the queue's)."""
        group = group or self.group
        event = self._cl.enqueue_nd_range_kernel(
            self.queue, kernel, (padded_size(n, group or 64),), None if group is None else (group,)
        )
        if self.launches is not None:
            self.launches.append((kernel.function_name, event))

    def kernel_times(self) -> dict[str, tuple[int, float]]:
        """Kernel name -> (launches, seconds on the device) of the launches since
        the last call (waits for the queue); empty unless the queue profiles."""
        if self.launches is None:
            return {}
        self.queue.finish()
        times: dict[str, tuple[int, float]] = {}
        for name, event in self.launches:
            count, seconds = times.get(name, (0, 0.0))
            times[name] = (count + 1, seconds + (event.profile.end - event.profile.start) * 1e-9)
        self.launches.clear()
        return times

    def upload(self, buffer, array: np.ndarray):
        """Queue a copy of ``array`` into ``buffer``; its event."""
        return self._cl.enqueue_copy(self.queue, buffer, array, is_blocking=False)

    def put_params(self, packed, uploads: list) -> tuple:
        """The buffers ``params`` and ``lists`` holding a frame's
        :class:`~marblevideo.opencl.program.Packed` values (copy events appended
        to ``uploads``)."""
        pbuf = self.buffer("params", packed.params.nbytes)
        lbuf = self.buffer("lists", packed.lists.nbytes)
        uploads.append(self.upload(pbuf, packed.params))
        uploads.append(self.upload(lbuf, packed.lists))
        return pbuf, lbuf

    def put_rgba(self, rgba: np.ndarray, padded):
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

    def put_i420(self, planes: tuple[np.ndarray, np.ndarray, np.ndarray], events: list):
        """The buffer ``i420_in`` holding ``planes`` packed (see marblevideo.media.yuv);
        rows padded on the host are copied by a rectangle copy, not packed first.
        The copies' events are appended to ``events``."""
        cl = self._cl
        staged = self.buffer("i420_in", sum(p.shape[0] * p.shape[1] for p in planes))
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

    def download(
        self, result: np.ndarray, src, wait: bool, uploads: list, errors: Callable
    ) -> np.ndarray | Callable[[], np.ndarray]:
        """Copy the device buffer ``src`` into ``result`` and return it; or, unless
        ``wait``, queue the copy and return a function that waits for it and
        returns ``result``, holding ``uploads`` (the events of the frame's copies
        from the host, which hold their arrays) until then. ``errors``: the
        context manager that turns an OpenCL error while waiting into DeviceError."""
        download = self._cl.enqueue_copy(self.queue, result, src, is_blocking=wait)
        if wait:
            return result

        def finish() -> np.ndarray:
            with errors():
                download.wait()
            uploads.clear()
            return result

        return finish

    def read(self, array: np.ndarray, buffer) -> np.ndarray:
        """Copy the start of ``buffer`` into ``array`` and return it (waits for the queue)."""
        self._cl.enqueue_copy(self.queue, array, buffer, is_blocking=True)
        return array

    def count(self, counter) -> int:
        """Read the int32 in ``counter`` (waits for the queue up to it)."""
        count = np.empty(1, np.int32)
        self._cl.enqueue_copy(self.queue, count, counter, is_blocking=True)
        return int(count[0])
