#include "podium/base/native_blas.h"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>

namespace podium::base {

int cpu_vector_bits() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  // __builtin_cpu_supports also checks that the OS saves the wide registers (XGETBV).
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
    return 512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return 256;
#endif
  return 0;
}

namespace {
// The widest vectors a core's kernels use; -1 for a name not listed (a newer OpenBLAS's: left alone).
int core_bits(std::string core) {
  std::transform(core.begin(), core.end(), core.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* wide : {"skylakex", "cooperlake", "sapphirerapids"})
    if (core == wide) return 512;
  for (const char* avx2 : {"haswell", "zen", "excavator"})
    if (core == avx2) return 256;
  for (const char* narrow :
       {"prescott", "core2", "penryn", "dunnington", "nehalem", "sandybridge", "atom", "katmai", "coppermine", "northwood",
        "banias", "opteron", "opteron_sse3", "barcelona", "bobcat", "bulldozer", "piledriver", "steamroller", "nano"})
    if (core == narrow) return 0;
  return -1;
}
}  // namespace

std::string openblas_core_override(const std::string& chosen, int cpu_bits) {
  const int bits = core_bits(chosen);
  if (bits < 0 || bits >= cpu_bits) return "";
  return cpu_bits >= 512 ? "SkylakeX" : cpu_bits >= 256 ? "Haswell" : "";
}

std::string openblas_core_name() {
  using CoreName = char* (*)();
  auto core_name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  if (core_name == nullptr)
    if (void* library = dlopen("libopenblas.so.0", RTLD_LAZY | RTLD_LOCAL))
      core_name = reinterpret_cast<CoreName>(dlsym(library, "openblas_get_corename"));
  const char* name = core_name != nullptr ? core_name() : nullptr;
  return name != nullptr ? std::string(name) : std::string();
}

}  // namespace podium::base
