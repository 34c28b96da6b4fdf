#include "hand_over.h"

#include <algorithm>
#include <filesystem>
#include <map>

#include "podium/store/store.h"

namespace podium::orchestrator {

using base::Json;

namespace {

// Trials without a primary objective cannot be ranked; they are never "best".
bool ranked(const store::TrialRecord& t) { return t.objectives.is_array() && !t.objectives.empty(); }
double objective(const store::TrialRecord& t) { return t.objectives[0].get<double>(); }

Json input_trial(const store::StageRecord& stage, const store::TrialRecord& t, const store::Store& store) {
  Json artifacts = Json::object();
  for (const auto& a : store.artifacts(t.id)) artifacts[a.name] = std::filesystem::absolute(a.path).lexically_normal().string();
  return {{"stage", stage.name},
          {"stage_index", stage.index},
          {"trial_index", t.index},
          {"params", t.params},
          {"objectives", t.objectives.is_array() ? t.objectives : Json::array()},
          {"features", t.features},
          {"strategy", t.strategy ? Json(*t.strategy) : Json(nullptr)},
          {"artifacts", artifacts},
          {"info", t.result_info.is_object() ? t.result_info : Json::object()}};
}

// The selected trials of one stage, in hand-over order.
std::vector<store::TrialRecord> select(std::vector<store::TrialRecord> done, const InputsSpec& inputs) {
  if (inputs.select == "all") return done;
  std::vector<store::TrialRecord> candidates;
  for (auto& t : done)
    if (ranked(t)) candidates.push_back(std::move(t));
  // Stable: among equal objectives the earlier trial comes first.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return objective(a) > objective(b); });
  if (inputs.select == "best") candidates.resize(std::min<std::size_t>(candidates.size(), 1));
  if (inputs.select == "top") candidates.resize(std::min<std::size_t>(candidates.size(), inputs.top_k));
  if (inputs.select != "best_per_strategy") return candidates;
  std::map<std::int64_t, store::TrialRecord> best;  // by strategy id; candidates are best first
  for (auto& t : candidates)
    if (t.strategy && !best.count(*t.strategy)) best.emplace(*t.strategy, std::move(t));
  std::vector<store::TrialRecord> out;
  for (auto& [strategy, t] : best) out.push_back(std::move(t));
  return out;
}

}  // namespace

Json select_input_trials(const store::Store& store, const std::vector<store::StageRecord>& stages, const InputsSpec& inputs) {
  Json out = Json::array();
  for (const auto& name : inputs.stages) {
    const auto& stage = *std::find_if(stages.begin(), stages.end(), [&](const auto& s) { return s.name == name; });
    std::vector<store::TrialRecord> done;
    for (auto& t : store.trials(stage.id))
      if (t.state == "done") done.push_back(std::move(t));
    for (const auto& t : select(std::move(done), inputs)) out.push_back(input_trial(stage, t, store));
  }
  return out;
}

std::string empty_selection_reason(const store::Store& store, const std::vector<store::StageRecord>& stages,
                                   const InputsSpec& inputs) {
  std::string names;
  for (const auto& name : inputs.stages) names += (names.empty() ? "\"" : ", \"") + name + "\"";
  std::string why = "selecting \"" + inputs.select + "\" from stage " + names + " gave none";
  if (inputs.select != "best_per_strategy") return why;
  for (const auto& name : inputs.stages) {
    const auto& stage = *std::find_if(stages.begin(), stages.end(), [&](const auto& s) { return s.name == name; });
    std::size_t done = 0;
    for (const auto& t : store.trials(stage.id)) done += t.state == "done" ? 1 : 0;
    const Json rule = stage.description.value("success", Json());
    why +=
        "; stage \"" + name + "\" found no strategy in " + std::to_string(done) + " done trials" +
        (rule.is_null() ? "" : " (none succeeded by its task's success rule " + rule.dump() + "; a failed trial is no strategy)");
  }
  return why;
}

std::size_t input_for_trial(std::int64_t trial_index, std::optional<std::size_t> proposed, std::size_t n) {
  return proposed ? *proposed : static_cast<std::size_t>(trial_index) % n;
}

std::optional<std::size_t> recorded_input(const Json& trial_info) {
  if (!trial_info.contains("input")) return std::nullopt;
  return trial_info["input"].get<std::size_t>();
}

Json inputs_of_trial(const Json& input_trials, const InputsSpec& inputs, std::optional<std::size_t> input) {
  if (inputs.per_trial == "all") return input_trials;
  return Json::array({input_trials.at(input.value())});
}

}  // namespace podium::orchestrator
