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
  double strategy_threshold = 0.0;   ///< feature distance within which trials are one strategy; 0 = the task's default
};

/// Where trials run: "local" (worker processes on this machine) or "slurm" (jobs on a cluster;
/// the run folder must be on a filesystem the compute nodes share).
struct ExecutorSpec {
  std::string kind = "local";
  std::string partition;              ///< slurm: required
  std::string account;                ///< slurm: optional
  std::string time;                   ///< slurm: job time limit, Slurm syntax ("30", "01:00:00")
  int cpus_per_task = 1;
  std::string mem;                    ///< slurm: e.g. "4G"; "" = the partition's default
  std::vector<std::string> extra_sbatch;  ///< passed to sbatch as they are
  int max_jobs_in_queue = 100;        ///< at most this many of the campaign's jobs queued or running
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
