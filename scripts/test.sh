#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every CTest test: unit and
# end-to-end tests, the learning checks (label learning), the Slurm tests (label slurm) and the
# dashboard's load test (label load, run alone since it measures throughput).
# Usage: scripts/test.sh [ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# One BLAS/OpenMP thread per process: the suite runs two tests at a time on two cores.
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
ctest --test-dir build -j "$(nproc)" --output-on-failure "$@"
