#pragma once
// A task's campaign run to its end through the real `podium` CLI, its stages' trials read back
// from the store: what a task's end-to-end campaign test checks (tests/tasks/*/..._task_test.cpp).
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "podium/store/store.h"

namespace podium::testing {

struct FinishedCampaign {
  std::int64_t id = 0;
  std::unique_ptr<store::Store> store;                            ///< read-only
  std::map<std::string, std::vector<store::TrialRecord>> trials;  ///< by stage name, in index order

  std::set<std::string> artifact_names(const store::TrialRecord& trial) const;
  std::set<std::string> metric_names(const store::TrialRecord& trial) const;
};

/// Submits `spec` in `dir` (its podium.db), runs `podium run` there and reads every stage back.
/// Throws std::runtime_error, with podium's stderr or the stage's or trial's error, unless the run
/// exits 0 and every stage and every trial is done.
FinishedCampaign run_campaign_to_end(const std::filesystem::path& dir, const nlohmann::json& spec);

}  // namespace podium::testing
