#pragma once
/// Campaign specs: the JSON a researcher submits (schema: campaigns/campaign.schema.json).
/// parse_spec validates everything that can be checked without loading a plugin; unknown keys,
/// wrong types and out-of-range values are base::UserError naming the JSON path.
#include <cstdint>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::orchestrator {

using base::Json;

struct StageSpec {
  std::string name;
  std::string task;                  ///< plugin name
  std::string preset;                ///< "" = none
  Json config = Json::object();      ///< overrides on top of the preset
  std::string algorithm;             ///< search algorithm
  Json search_config = Json::object();
  std::int64_t budget_trials = 0;
  double budget_seconds = 0.0;       ///< 0 = no wall-time budget
  Json inputs = nullptr;             ///< {"stage": name, "select": "all"|"best"} or null
};

struct ExecutorSpec {
  std::string kind = "local";
};

struct CampaignSpec {
  std::string name;
  std::uint64_t seed = 0;
  std::string description;
  std::string run_dir;               ///< "" = <database>.runs/<campaign id>
  ExecutorSpec executor;
  int workers = 2;                   ///< at most this many trials of the campaign at once
  int retries = 2;                   ///< attempts after the first before a trial fails
  double trial_timeout_s = 3600.0;
  std::vector<StageSpec> stages;
};

/// Validates and parses; `source` (usually the file name) prefixes every error.
CampaignSpec parse_spec(const Json& j, const std::string& source);

}  // namespace podium::orchestrator
