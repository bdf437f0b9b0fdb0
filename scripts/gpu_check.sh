#!/usr/bin/env bash
# The GPU checks of a session lent a GPU machine: the kernels against the NumPy
# reference on the GPU, then the benchmarks that BENCHMARKS.md records for GPUs.
#   bash scripts/gpu_check.sh [OUTDIR]      (default: the current folder)
# Needs the package's dependencies importable (a venv, or wheels installed with
# `pip install --target DIR` and DIR on PYTHONPATH), pytest and pytest-xdist, and
# an OpenCL driver for the GPU. NVIDIA's driver ships libnvidia-opencl.so.1, but
# containers often lack its ICD file: where the library is found and no
# nvidia.icd is registered, this writes one (as root).
set -uo pipefail
out=$(realpath "${1:-.}")
cd "$(dirname "$0")/.."
export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" PYTHONUNBUFFERED=1
if [ ! -e /etc/OpenCL/vendors/nvidia.icd ]; then
    lib=$(ldconfig -p 2>/dev/null | grep -o '/[^ ]*libnvidia-opencl.so.1' | head -1)
    [ -z "$lib" ] && lib=$(find /usr/local/nvidia /usr/lib* -name 'libnvidia-opencl.so.1' 2>/dev/null | head -1)
    if [ -n "$lib" ]; then
        { mkdir -p /etc/OpenCL/vendors && echo "$lib" > /etc/OpenCL/vendors/nvidia.icd; } ||
            echo "found $lib but cannot register it in /etc/OpenCL/vendors (not root?)"
    fi
fi
python3 -m marblevideo devices | tee "$out/devices.txt"
python3 -m marblevideo devices | grep -q '^\*.*GPU' || { echo "no GPU is the default device"; exit 1; }
timeout 300 python3 -m pytest -q -p no:cacheprovider -n "$(nproc)" -rf \
    tests/test_kernel.py tests/test_reused_maps.py tests/test_lattice.py tests/test_vector.py \
    tests/test_yuv.py tests/test_stroke.py tests/test_presets.py tests/test_reference.py \
    tests/test_vocabulary.py tests/test_zoom.py tests/test_tiling.py tests/test_op_registry.py \
    2>&1 | tee "$out/gpu-tests.txt" | tail -15
timeout 400 python3 -m benchmarks table1 lattice live1080 e2e --seconds 30 2>&1 | tee "$out/gpu-bench.txt"
