#pragma once
/// What a campaign found, per stage: `podium summary` and the dashboard's campaign panel.
///
/// campaign_summary's JSON (every list in the task's or the stage's order):
///   {"campaign": {"id", "name", "state"},
///    "stages": [{
///      "index", "name", "task", "algorithm", "state",
///      "config": {...},                                   // the task config it ran with
///      "trials": {"budget", "done", "failed", "running", "pending", "cancelled"},
///      "objectives": [{"name", "unit"?, "description"?}],   // objectives[0] ranks trials
///      "features":   [{"name", "unit"?, "description"?}],
///      "best": null | {"trial": "stage/index", "index", "id", "strategy": id|null, "strategy_label": label|null,
///                      "objectives": [{"name", "unit"?, "value"}], "features": [{"name", "unit"?, "value"}]},
///      "strategies": [{"id", "label", "trials", "best_objective",
///                      "representative": {"trial": "stage/index", "index", "id"},
///                      "features": [{"name", "unit"?, "value"}]}],       // the representative's
///      "discovery": [[samples, strategies], ...],
///      "tables": [{"title", "columns": [{"name", "unit"?}], "rows": [[cell, ...], ...]}]}]}
/// - "best" and each strategy's representative: the done trial with the highest objectives[0]
///   (the lower index on a tie). A strategy's "id" is the store's (its cell of the strategy grid, the
///   key in filters and URLs); its "label" (1..n, StrategyLabels in store.h) is what users read.
///   "strategies" in label order.
/// - "discovery": done trials in the order they finished; samples = done trials so far,
///   strategies = distinct strategy ids among them. One point where the count rises, and the last
///   sample (a step curve); empty without done trials.
/// - "tables": the per-task tables of the stage's done trials (RunResult::info["table"], see
///   plugins/task.h), those with the same title and columns merged, each row led by a "trial" column.
/// Costs: per stage one walk of an index over its done trials (a few columns each; the result
/// info only of trials that give a table), then one read per best trial and representative.
#include <cstdint>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::store {

class Store;

/// A number at the shortest precision that reads back to the same double (std::to_chars);
/// "nan", "inf", "-inf" for those.
std::string format_number(double value);

/// A stage description's objectives as [{"name", "unit"?, "description"?}], in the task's order.
/// A description without "objective_info" (an older store) gives the names alone.
base::Json objective_entries(const base::Json& description);

/// A stage description's features as [{"name", "unit"?, "description"?}], in the task's order.
base::Json feature_entries(const base::Json& description);

/// The summary of campaign `campaign_id` (the JSON above). Throws base::UserError without it.
base::Json campaign_summary(const store::Store& store, std::int64_t campaign_id);

/// Several campaigns' summaries side by side:
///   {"campaigns": [campaign_summary, ...],
///    "stages": [{"name", "curves": [{"campaign": id, "campaign_name", "discovery": [[samples, strategies], ...]}]}]}
/// "stages" pairs stages by name, in the order they first appear; a campaign without the stage
/// has no curve in it.
base::Json compare_campaigns(const store::Store& store, const std::vector<std::int64_t>& campaign_ids);

/// compare_campaigns of summaries already made (campaign_summary's JSON each, in that order).
base::Json compare_summaries(const std::vector<base::Json>& summaries);

/// campaign_summary's JSON as text (what `podium summary CAMPAIGN` prints). `brief` (`--short`,
/// what the demo prints): per stage its trials, best trial, strategy count and the task's tables,
/// without the objectives' descriptions, the strategy table and the discovery curve.
std::string format_summary(const base::Json& summary, bool brief = false);

/// compare_campaigns's JSON as text: per stage, each campaign's figures and tables side by side.
std::string format_comparison(const base::Json& comparison);

}  // namespace podium::store
