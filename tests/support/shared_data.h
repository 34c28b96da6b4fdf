#pragma once
// Test support: ../shared/data, the characters, clips and captured motions beside the repository
// (never copied into it). A test that reads it skips with a printed reason when it is absent.
#include <cstdlib>
#include <filesystem>
#include <string_view>

namespace podium::testing {

/// PODIUM_SHARED_DIR/data/`relative` (test_main.cpp defaults the variable to the configured
/// ../shared), or empty when the variable is unset or that path does not exist.
inline std::filesystem::path shared_data(std::string_view relative = {}) {
  const char* shared = std::getenv("PODIUM_SHARED_DIR");
  if (shared == nullptr || *shared == '\0') return {};
  std::filesystem::path path = std::filesystem::path(shared) / "data";
  if (!relative.empty()) path /= relative;
  return std::filesystem::exists(path) ? path : std::filesystem::path{};
}

}  // namespace podium::testing
