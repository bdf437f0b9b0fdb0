"""Choosing an OpenCL device.

One function decides, in this order: an explicit ``--device`` choice, then
the ``PYOPENCL_CTX`` environment variable (pyopencl's own convention), then the
fastest GPU, else a CPU device (PoCL). A choice is ``P:D`` (platform and
device index as listed by ``marblevideo devices``), ``P``, or a
case-insensitive part of the device or platform name.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from marblevideo.errors import DeviceError, UsageError

HOW_TO_GET_ONE = (
    "install an OpenCL driver: on Debian/Ubuntu `sudo apt-get install pocl-opencl-icd` "
    "(runs on the CPU), or `pip install pyopencl[pocl]`, or your GPU vendor's OpenCL driver"
)


@dataclass(frozen=True)
class DeviceInfo:
    platform_index: int
    device_index: int
    platform: str
    name: str
    kind: str
    compute_units: int
    clock_mhz: int
    device: object  # pyopencl.Device

    @property
    def label(self) -> str:
        return f"{self.platform_index}:{self.device_index}"


def _cl():
    try:
        import pyopencl as cl
    except ImportError as exc:  # pragma: no cover - dependency of the package
        raise DeviceError(f"pyopencl cannot be imported ({exc}); {HOW_TO_GET_ONE}") from None
    return cl


def list_devices() -> list[DeviceInfo]:
    """Every OpenCL device of every platform; empty when there is none."""
    cl = _cl()
    try:
        platforms = cl.get_platforms()
    except cl.Error:
        return []
    found = []
    for pi, platform in enumerate(platforms):
        try:
            devices = platform.get_devices()
        except cl.Error:
            continue
        for di, dev in enumerate(devices):
            kind = cl.device_type.to_string(dev.type).replace("ALL | ", "")
            found.append(
                DeviceInfo(
                    pi,
                    di,
                    platform.name.strip(),
                    dev.name.strip(),
                    kind,
                    int(dev.max_compute_units),
                    int(dev.max_clock_frequency),
                    dev,
                )
            )
    return found


def _is_gpu(info: DeviceInfo) -> bool:
    return "GPU" in info.kind


def _match(devices: list[DeviceInfo], choice: str, origin: str) -> DeviceInfo:
    choice = choice.strip()
    parts = choice.split(":")
    if all(p.isdigit() for p in parts if p) and parts[0]:
        pi = int(parts[0])
        di = int(parts[1]) if len(parts) > 1 and parts[1] else 0
        for info in devices:
            if (info.platform_index, info.device_index) == (pi, di):
                return info
    else:
        needle = choice.lower()
        for info in devices:
            if needle in info.name.lower() or needle in info.platform.lower():
                return info
    known = ", ".join(f"{d.label} {d.name}" for d in devices)
    raise UsageError(f"{origin}: no OpenCL device matches {choice!r}; devices: {known}")


def choose_device(choice: str | None = None) -> DeviceInfo:
    """The device to render on (see the module docstring for the order)."""
    devices = list_devices()
    if not devices:
        raise DeviceError(f"no OpenCL device found; {HOW_TO_GET_ONE}")
    if choice:
        return _match(devices, choice, "--device")
    env = os.environ.get("PYOPENCL_CTX")
    if env:
        return _match(devices, env, "PYOPENCL_CTX")
    gpus = [d for d in devices if _is_gpu(d)]
    pool = gpus or [d for d in devices if "CPU" in d.kind] or devices
    return max(pool, key=lambda d: d.compute_units * max(d.clock_mhz, 1))


def describe_devices() -> str:
    """The text of ``marblevideo devices``: one line per device, default marked."""
    devices = list_devices()
    if not devices:
        return f"no OpenCL device found; {HOW_TO_GET_ONE}"
    try:
        default = choose_device(None).label
    except (DeviceError, UsageError):
        default = None
    lines = []
    for d in devices:
        mark = "*" if d.label == default else " "
        lines.append(
            f"{mark} {d.label}  {d.name}  [{d.kind}, {d.compute_units} compute units, "
            f"{d.clock_mhz} MHz]  platform: {d.platform}"
        )
    lines.append("(* = default; choose with --device P:D, a name, or PYOPENCL_CTX)")
    return "\n".join(lines)
