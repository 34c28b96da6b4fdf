#pragma once
/// Campaign specs: the JSON a researcher submits (schema: campaigns/campaign.schema.json).
/// parse_spec validates everything that can be checked without loading a plugin; unknown keys,
/// wrong types and out-of-range values are base::UserError naming the JSON path.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::orchestrator {

using base::Json;

/// The most trials a campaign runs at once ("workers") and worker processes `podium run` starts.
inline constexpr int kMaxWorkers = 1024;

/// The most trials a stage's budget holds (budget.trials, and `podium extend`).
inline constexpr std::int64_t kMaxTrials = 10'000'000;

/// A stage's hand-over (docs/architecture.md "Stage hand-over"): which finished trials of earlier stages its
/// trials and its search receive. Resolved when the stage starts, then stored with it.
struct InputsSpec {
  std::vector<std::string> stages;  ///< earlier stages, in the order their trials are handed over
  std::string select = "all";       ///< per stage: all | best | best_per_strategy | top (by objectives[0])
  int top_k = 0;                    ///< "top": how many (at most; fewer if the stage has fewer)
  std::string per_trial = "all";    ///< all: every trial gets every input; each: trial i gets input i mod n
};

/// The stored form: {"stages": [...], "select", "k" (top only), "per_trial"}.
Json to_json(const InputsSpec& inputs);

struct StageSpec {
  std::string name;
  std::string task;              ///< plugin name
  std::string preset;            ///< "" = none
  Json config = Json::object();  ///< overrides on top of the preset
  std::string algorithm;         ///< search algorithm
  Json search_config = Json::object();
  std::int64_t budget_trials = 0;     ///< 0 with budget_per_input: set when the stage starts
  std::int64_t budget_per_input = 0;  ///< budget.trials {"per_input": k}: k trials per input; 0 = fixed
  double budget_seconds = 0.0;        ///< 0 = no wall-time budget
  std::optional<InputsSpec> inputs;
  double strategy_threshold = 0.0;  ///< feature distance within which trials are one strategy; 0 = the task's default
};

/// Where trials run: "local" (worker processes on this machine) or "slurm" (jobs on a cluster;
/// the run folder must be on a filesystem the compute nodes share).
struct ExecutorSpec {
  std::string kind = "local";
  std::string partition;  ///< slurm: required
  std::string account;    ///< slurm: optional
  std::string time;       ///< slurm: job time limit, Slurm syntax ("30", "01:00:00")
  int cpus_per_task = 1;
  std::string mem;                        ///< slurm: e.g. "4G"; "" = the partition's default
  std::vector<std::string> extra_sbatch;  ///< passed to sbatch as they are
  int max_jobs_in_queue = 100;            ///< at most this many of the campaign's jobs queued or running
};

struct CampaignSpec {
  std::string name;
  std::uint64_t seed = 0;
  std::string description;
  std::string run_dir;  ///< "" = <database>.runs/<campaign id>
  ExecutorSpec executor;
  int workers = 2;  ///< at most this many trials of the campaign at once
  int retries = 2;  ///< failed attempts run again before a trial fails (interrupted ones do not count)
  double trial_timeout_s = 3600.0;
  std::vector<StageSpec> stages;
};

/// Validates and parses; `source` (usually the file name) prefixes every error.
CampaignSpec parse_spec(const Json& j, const std::string& source);

}  // namespace podium::orchestrator
