#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every CTest test (unit tests and
# the labelled learning checks). Usage: scripts/test.sh [extra ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# One BLAS/OpenMP thread per process: the suite runs two tests at a time on two cores.
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
ctest --test-dir build -j "$(nproc)" --output-on-failure "$@"
