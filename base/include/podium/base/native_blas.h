#pragma once
/// OpenBLAS picks its kernels from the CPU's model number when it loads. A model newer than the
/// installed OpenBLAS knows (Debian 12's 0.3.21 on a 5th-generation Xeon, model 207) falls back to
/// its oldest x86-64 kernels ("Prescott"), which run sgemm — most of a network update — 4-5x
/// slower than the AVX-512 ones the CPU has. OPENBLAS_CORETYPE, set before the library loads,
/// overrides the choice. These are the pure parts of that decision; the podium binary applies it
/// at start (orchestrator/src/native_blas.cpp), and learn/ warns in other hosts.
#include <string>

namespace podium::base {

/// The widest vector instruction set this CPU and OS run: 512 (AVX-512 F, CD, BW, DQ and VL, what
/// OpenBLAS's SkylakeX kernels use), 256 (AVX2 and FMA: its Haswell kernels) or 0 (neither).
int cpu_vector_bits();

/// The core type to force when OpenBLAS chose `chosen` (openblas_get_corename()) on a CPU of
/// `cpu_bits`: "SkylakeX" or "Haswell" when the choice's kernels are narrower than the CPU runs,
/// else "" (OpenBLAS's own choice stands, also for a name not listed here). Cores are compared by
/// the widest vectors their kernels use: SkylakeX, Cooperlake, SapphireRapids 512; Haswell, Zen,
/// Excavator 256; the older ones OpenBLAS 0.3 names (Prescott, Core2, Nehalem, Sandybridge, …) 0.
std::string openblas_core_override(const std::string& chosen, int cpu_bits);

/// The core whose kernels OpenBLAS runs in this process (openblas_get_corename()): the loaded
/// BLAS's when it is OpenBLAS, else libopenblas.so.0's as it loads with this environment; "" when
/// OpenBLAS is not installed.
std::string openblas_core_name();

}  // namespace podium::base
