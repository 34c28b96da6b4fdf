#pragma once
// Test support: one trial through the real `podium trial --batch` (the Slurm executor's path:
// order.json in, metrics.jsonl and result.json out), shared by the task tests.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "process.h"

namespace podium::testing {

/// A worker's order with the fields every test sets; the rest are a first attempt of trial 0.
struct TrialOrder {
  std::string task;
  nlohmann::json config = nlohmann::json::object();
  nlohmann::json params = nlohmann::json::object();
  nlohmann::json inputs = nlohmann::json::array();
  nlohmann::json previous_attempt = nullptr;  ///< {"number", "state", "error"} on a retry
  std::uint64_t seed = 1;
  int attempt = 1;
  std::filesystem::path work_dir;
};

/// The order as `podium trial` reads it.
nlohmann::json order_json(const TrialOrder& o);

/// What one `podium trial --batch` process left in its folder.
struct BatchTrial {
  CommandResult run;                    ///< its exit code and stderr
  nlohmann::json result;                ///< result.json (null when it wrote none)
  std::vector<nlohmann::json> metrics;  ///< metrics.jsonl, one {"name", "step", "value"} per line
};

/// Writes order.json and batch.txt into attempt_dir and runs `podium trial --batch` there.
BatchTrial run_batch_trial(const nlohmann::json& order, const std::filesystem::path& attempt_dir);

}  // namespace podium::testing
