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
# The OpenBLAS kernels podium runs on this CPU (`podium version`; docs/user-guide.md, "Install"),
# for the test programs too: they load OpenBLAS before main, so they cannot choose for themselves.
if [ -z "${OPENBLAS_CORETYPE:-}" ]; then
  core=$(build/bin/podium version 2>/dev/null | sed -n 's/^openblas: \([A-Za-z0-9_]*\) kernels.*/\1/p' || true)
  if [ -n "$core" ]; then export OPENBLAS_CORETYPE=$core; fi
fi
ctest --test-dir build -j "$(nproc)" --output-on-failure "$@"
