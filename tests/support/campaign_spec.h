#pragma once
// Test support: single-stage campaign specs and `podium submit`, shared by the CLI, Slurm and
// dashboard tests so they exercise one spec shape.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "process.h"

namespace podium::testing {

/// The knobs tests vary; everything else is the smallest valid campaign.
struct StageSpec {
  std::string name = "test";
  std::uint64_t seed = 11;
  int workers = 2;
  int retries = 1;
  double trial_timeout_s = 30;
  std::string task = "landscape";
  std::string stage = "explore";
  std::string algorithm = "random";
  nlohmann::json config = nlohmann::json::object();  ///< omitted from the spec when null
  nlohmann::json executor = nullptr;                 ///< omitted (local executor) when null
  int trials = 10;
};

/// A one-stage campaign spec at the task's smoke preset.
nlohmann::json stage_spec(const StageSpec& s);

/// Writes `spec` to `dir/spec.json`, runs `podium submit` there and returns the campaign id it
/// prints; an error (with podium's stderr) if the submission fails.
std::string submit_spec(const std::filesystem::path& dir, const nlohmann::json& spec);

}  // namespace podium::testing
