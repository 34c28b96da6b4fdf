#include "run_folders.h"

namespace podium::orchestrator {

std::string stage_folder_name(int index, const std::string& name) {
  constexpr std::size_t kMaxName = 64;
  std::string safe;
  for (const char ch : name.substr(0, kMaxName)) {
    const bool keep = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '.' ||
                      ch == '_' || ch == '-';
    safe += keep ? ch : '_';
  }
  return "stage-" + std::to_string(index) + "-" + safe;
}

}  // namespace podium::orchestrator
