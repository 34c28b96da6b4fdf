#pragma once
/// Campaign-level operations behind the CLI: submit, control, extend, export.
#include <cstdint>
#include <filesystem>
#include <string>

#include "podium/base/json.h"

namespace podium::store {
class Store;
struct CampaignRecord;
}  // namespace podium::store

namespace podium::orchestrator {

/// Validates a spec (including each stage's task, preset, config and search config, asked of the
/// plugin in a separate worker process) and queues it in `database`. Returns the campaign id.
/// Paths in the spec are relative to `spec_dir` (the spec file's folder): `run_dir`, and every
/// config value the task declares a file ("format": "file" in its config description), which
/// must exist and is stored absolute. Throws base::UserError for spec errors (a missing file:
/// its JSON path, the path as written and as resolved); the database is opened (created if
/// absent) only once the whole spec is valid.
std::int64_t submit_campaign(const std::filesystem::path& database, const base::Json& spec, const std::string& source,
                             const std::filesystem::path& spec_dir, const std::filesystem::path& worker_binary);

/// pause: stop starting trials; resume: queue again; cancel: stop running trials, end the campaign.
/// Throws base::UserError if the campaign is in a state the action does not apply to.
void control_campaign(store::Store& store, const std::string& id_or_name, const std::string& action);

/// What `podium extend` changed.
struct Extension {
  std::int64_t campaign_id = 0;
  std::string campaign_name, stage;
  std::int64_t budget_before = 0, budget_after = 0;  ///< the stage's trial budget
};

/// Raises the trial budget of a done campaign's last stage by `add_trials` (`stage`: its name, or
/// "" for the last) and queues the campaign again. `podium run` then continues that stage's
/// search from its stored state: with 1 worker it proposes exactly the trials a run submitted
/// with the larger budget would have; with W workers the first W - 1 new trials are proposed
/// knowing every earlier result (an uninterrupted run would not yet have had the last W - 1).
/// Throws base::UserError when the campaign is not done, the stage is not its last, the stage
/// spent its wall-time budget, or the new budget is outside [1, kMaxTrials].
Extension extend_campaign(store::Store& store, const std::string& id_or_name, const std::string& stage, std::int64_t add_trials);

/// Every trial of a campaign as CSV (a header row, then one row per trial) or a JSON array (each
/// row also with its `name`, database `id` and result info). Objectives and features are named, in
/// the task's order: CSV columns `param.<name>`, `objective.<name>`, `feature.<name>` (over the
/// stages, in stage order), JSON objects {name: value} (an older store's unnamed values: `value<i>`).
/// Numbers at the shortest precision that round-trips. `metrics` (JSON only): each row also has
/// "metrics": {name: [[step, value], ...]}. "strategy" is the store's id (a cell of the strategy
/// grid), "strategy_label" what users read (store::StrategyLabels: 1..n per stage in the order found).
///   JSON row: {"campaign", "name", "id", "stage", "trial", "state", "attempts", "seed", "params",
///              "objectives", "features", "strategy", "strategy_label", "error", "started_at", "finished_at", "result",
///              "metrics"?}
std::string export_campaign(const store::Store& store, std::int64_t campaign_id, const std::string& format, bool metrics = false);

}  // namespace podium::orchestrator
