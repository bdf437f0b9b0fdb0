#!/usr/bin/env bash
# Set up with the test tools, then lint and run the whole test suite on the
# OpenCL device found (PoCL on a machine without a GPU).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --test
.venv/bin/ruff check marblevideo tests benchmarks samples scripts
.venv/bin/ruff format --check marblevideo tests benchmarks samples scripts
.venv/bin/python -m pytest -q "$@"
