#pragma once
// Reading rows into the store's record structs: one definition shared by the writer (store.cpp)
// and the read-only queries (queries.cpp).
#include <string>

#include "podium/store/store.h"
#include "sqlite.h"

namespace podium::store {

/// JSON text to Json; an empty text is null.
Json parse_json(const std::string& text);

/// SELECT of every TrialRecord column, the features as one JSON array; append WHERE/ORDER BY.
inline constexpr const char* kTrialSelect =
    "SELECT t.id, t.stage_id, t.idx, t.params, t.context, t.info, t.seed, t.state, t.attempts, t.objectives, "
    "t.result_info, t.strategy, t.error, t.created_at, t.started_at, t.finished_at, "
    "(SELECT json_group_array(value) FROM (SELECT value FROM features f WHERE f.trial_id = t.id ORDER BY idx)) "
    "FROM trials t ";

/// The current row of a kTrialSelect statement.
TrialRecord read_trial(const Statement& s);

}  // namespace podium::store
