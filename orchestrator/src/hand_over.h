#pragma once
// Stage hand-over (docs/architecture.md "Stage hand-over"): which earlier trials a stage's inputs select, and which
// of them each trial receives. The selection is made once, when the stage starts, and stored with
// the stage (store: start_stage), so a resumed stage hands over exactly what it did before.
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/orchestrator/spec.h"

namespace podium::store {
class Store;
struct StageRecord;
}  // namespace podium::store

namespace podium::orchestrator {

/// The done trials `inputs` selects, in the form search.h documents for SearchSetup::inputs
/// (artifact paths made absolute). Per named stage, in the order named: `all` in trial order;
/// `best` the highest primary objective (the earliest trial on a tie); `best_per_strategy` the
/// best of each strategy, by strategy id; `top` the k best, best first.
base::Json select_input_trials(const store::Store& store, const std::vector<store::StageRecord>& stages,
                               const InputsSpec& inputs);

/// Why `inputs` selected nothing, for the stage's error: "selecting ... from stage ... gave none",
/// and for best_per_strategy, per named stage, how many done trials it has and that none is a
/// strategy (none succeeded by its task's success rule: a failed trial has no strategy).
std::string empty_selection_reason(const store::Store& store, const std::vector<store::StageRecord>& stages,
                                   const InputsSpec& inputs);

/// Which input a new trial of a per_trial "each" stage receives: the one its proposal is for, else
/// trial_index mod n (n > 0).
std::size_t input_for_trial(std::int64_t trial_index, std::optional<std::size_t> proposed, std::size_t n);

/// The input a trial was given when it was created (its info's "input"), if any.
std::optional<std::size_t> recorded_input(const base::Json& trial_info);

/// The inputs one trial receives: every selected trial, or (per_trial "each") the one at `input`.
base::Json inputs_of_trial(const base::Json& input_trials, const InputsSpec& inputs, std::optional<std::size_t> input);

}  // namespace podium::orchestrator
