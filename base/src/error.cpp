#include "podium/base/error.h"

#include <cstdio>
#include <cstdlib>

namespace podium::base {

void check_failed(const char* condition, const char* file, int line, const std::string& detail) {
  std::fprintf(stderr, "podium: internal check failed at %s:%d: %s (%s)\n", file, line, condition, detail.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace podium::base
