#pragma once
// Reading rows into the store's record structs: one definition shared by the writer (store.cpp)
// and the read-only queries (queries.cpp).
#include <string>
#include <vector>

#include "podium/store/queries.h"
#include "podium/store/store.h"
#include "sqlite.h"

namespace podium::store {

/// JSON text to Json; an empty text is null.
Json parse_json(const std::string& text);

/// SELECT of every TrialRecord column but the features; append WHERE/ORDER BY.
inline constexpr const char* kTrialSelect =
    "SELECT t.id, t.stage_id, t.idx, t.params, t.context, t.info, t.seed, t.state, t.attempts, t.objectives, "
    "t.result_info, t.strategy, t.error, t.created_at, t.started_at, t.finished_at FROM trials t ";

/// A trial's feature values in order; bind the trial id. (Read as numbers: SQLite's JSON
/// functions print only 15 significant digits.)
inline constexpr const char* kTrialFeatures = "SELECT value FROM features WHERE trial_id = ? ORDER BY idx";

/// The current row of a kTrialSelect statement (features empty).
TrialRecord read_trial(const Statement& s);
/// The same row with the JSON columns as their stored text.
TrialText read_trial_text(const Statement& s);
/// A trial's features from a kTrialFeatures statement.
std::vector<double> read_features(Statement& features, std::int64_t trial_id);
/// Adds n trials in `state` to the counts (total and the state's own count).
void add_to_counts(TrialCounts& counts, const std::string& state, std::int64_t n);

}  // namespace podium::store
