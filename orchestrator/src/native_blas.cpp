#include "native_blas.h"

#include <unistd.h>

#include <cstdlib>
#include <string>

#include "podium/base/native_blas.h"

namespace podium::orchestrator {
namespace {
constexpr const char* kCoreType = "OPENBLAS_CORETYPE";
constexpr const char* kMarker = "PODIUM_OPENBLAS_CORETYPE";

std::string host_name() {
  char name[256] = {};
  return gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
}

}  // namespace

void use_native_blas_kernels(char** argv) {
  const char* set = std::getenv(kCoreType);
  const char* marker = std::getenv(kMarker);
  const std::string host = host_name();
  if (set != nullptr) {
    const bool podiums = marker != nullptr && std::string(marker).rfind(std::string(set) + "@", 0) == 0;
    if (!podiums) return;                                              // the user's choice stands
    if (std::string(marker) == std::string(set) + "@" + host) return;  // decided on this machine
    unsetenv(kCoreType);                                               // decided on another machine
    unsetenv(kMarker);
  }
  const std::string core = base::openblas_core_override(base::openblas_core_name(), base::cpu_vector_bits());
  if (core.empty()) return;
  setenv(kCoreType, core.c_str(), 1);
  setenv(kMarker, (core + "@" + host).c_str(), 1);
  execv("/proc/self/exe", argv);  // returns only on failure: go on with OpenBLAS's own kernels
  unsetenv(kCoreType);
  unsetenv(kMarker);
}

std::string blas_kernels_line() {
  const std::string core = base::openblas_core_name();  // the library is loaded with this process's environment
  if (core.empty()) return "openblas: not found";
  const char* set = std::getenv(kCoreType);
  const char* marker = std::getenv(kMarker);
  const std::string who = set == nullptr ? "OpenBLAS's own choice"
                          : marker != nullptr && std::string(marker).rfind(std::string(set) + "@", 0) == 0
                              ? "chosen by podium for this CPU"
                              : "OPENBLAS_CORETYPE as set";
  return "openblas: " + core + " kernels (" + who + ")";
}

}  // namespace podium::orchestrator
