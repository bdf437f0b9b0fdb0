#!/usr/bin/env bash
# Set up with the test tools, then lint and run the whole test suite on the
# OpenCL device found (PoCL on a machine without a GPU). Arguments go to pytest
# (`bash scripts/test.sh -m fast`, `bash scripts/test.sh tests/test_cli.py -x`);
# it prints the 15 slowest tests (a later --durations=N wins) and, last, the
# suite's wall time, whether it passed or not.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --test
.venv/bin/ruff check marblevideo tests benchmarks samples scripts
.venv/bin/ruff format --check marblevideo tests benchmarks samples scripts
start=$SECONDS
status=0
.venv/bin/python -m pytest -q --durations=15 "$@" || status=$?
took=$((SECONDS - start))
printf 'scripts/test.sh: pytest took %dm%02ds wall time (exit status %d)\n' \
    $((took / 60)) $((took % 60)) "$status"
exit "$status"
