#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every CTest test: unit and
# end-to-end tests, the learning checks (label learning) and the Slurm tests (label slurm).
# The dashboard's load test (label load: throughput under a hammering client, a ratio this
# shared 2-core machine measures with noise as large as its 20% bar) runs on request:
#   scripts/test.sh -L load
# Usage: scripts/test.sh [ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# One BLAS/OpenMP thread per process: the suite runs two tests at a time on two cores.
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
if (($#)); then args=("$@"); else args=(-LE load); fi
ctest --test-dir build -j "$(nproc)" --output-on-failure "${args[@]}"
