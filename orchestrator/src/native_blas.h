#pragma once
// Before anything loads OpenBLAS (a task plugin brings libtorch and it): when the installed
// OpenBLAS would run its generic kernels on this CPU (base/native_blas.h), set OPENBLAS_CORETYPE
// to the kernels the CPU runs and start this program again with the same arguments, so this
// process and every worker it starts use them. A value the user set stands. The value podium set
// is marked with the host (PODIUM_OPENBLAS_CORETYPE=core@host), so a worker on another machine
// (Slurm) decides afresh for its own CPU.
#include <string>

namespace podium::orchestrator {

void use_native_blas_kernels(char** argv);

/// `podium version`'s line on them: "openblas: CORE kernels (WHO chose them)", WHO being podium
/// for this CPU, OPENBLAS_CORETYPE as the user set it, or OpenBLAS itself; "openblas: not found"
/// without it. scripts/test.sh exports CORE for the test programs, which load OpenBLAS before main.
std::string blas_kernels_line();

}  // namespace podium::orchestrator
