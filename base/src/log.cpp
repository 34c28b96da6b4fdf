#include "podium/base/log.h"

#include <atomic>
#include <cstdio>

namespace podium::base {

namespace {
std::atomic<LogLevel> g_level{LogLevel::info};
const char* level_name(LogLevel level) {
  switch (level) {
    case LogLevel::debug:
      return "debug";
    case LogLevel::info:
      return "info";
    case LogLevel::warning:
      return "warning";
    case LogLevel::error:
      return "error";
    default:
      return "";
  }
}
}  // namespace

void set_log_level(LogLevel level) { g_level = level; }
LogLevel log_level() { return g_level; }

void log(LogLevel level, const std::string& message) {
  if (level < g_level.load()) return;
  std::fprintf(stderr, "podium %s: %s\n", level_name(level), message.c_str());
}

}  // namespace podium::base
