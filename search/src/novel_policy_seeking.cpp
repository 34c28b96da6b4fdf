#include "novel_policy_seeking.h"

#include <cmath>

#include "podium/base/config.h"
#include "podium/base/error.h"

namespace podium::search {

using base::UserError;

NovelPolicyParams NovelPolicyParams::from_json(const Json& config, const std::string& path) {
  base::ConfigReader r(config, path);
  NovelPolicyParams p;
  p.trials_per_input = r.integer("trials_per_input", p.trials_per_input, {1, 100000});
  p.d_threshold = r.number("d_threshold", p.d_threshold, {1e-12, 1e300});
  p.warm_start_artifact = r.string("warm_start_artifact", p.warm_start_artifact);
  r.finish();
  return p;
}

NovelPolicySeeking::NovelPolicySeeking(const SearchSetup& setup, const std::string& json_path)
    : space_(setup.space), features_(setup.features), params_(NovelPolicyParams::from_json(setup.config, json_path + ".config")) {
  const std::string path = json_path + ".inputs";
  if (!setup.inputs.is_array() || setup.inputs.empty())
    throw UserError(path + ": novel_policy needs the results of an earlier stage as inputs, got " + setup.inputs.dump());
  for (std::size_t i = 0; i < setup.inputs.size(); ++i) {
    const Json& in = setup.inputs[i];
    const std::string at = base::json_path_index(path, i);
    Input input;
    if (!in.contains("params") || !in["params"].is_object()) throw UserError(at + ".params: missing or not an object");
    for (const auto& p : space_.params) {
      const Json* v = in["params"].contains(p.name) ? &in["params"][p.name] : nullptr;
      if (!v || !v->is_number() || v->get<double>() < p.low || v->get<double>() > p.high)
        throw UserError(at + ".params." + p.name + ": " + (v ? v->dump() : "missing") + " is not a number in [" +
                        Json(p.low).dump() + ", " + Json(p.high).dump() + "]");
      input.x.push_back(v->get<double>());
    }
    const Json features = in.value("features", Json::array());
    if (!features.is_array()) throw UserError(at + ".features: " + features.dump() + " is not an array");
    // An input from a stage with other features (the jumps' Stage 1 up-angle beside Stage 2's
    // bar-frame rotation) cannot be compared with this stage's: the task reads its own from the
    // input trial it is handed, and `found` starts empty.
    if (!features.empty() && features.size() == features_.size()) input.found.push_back(features.get<std::vector<double>>());
    const Json artifacts = in.value("artifacts", Json::object());
    input.warm_start = artifacts.is_object() && artifacts.contains(params_.warm_start_artifact)
                           ? artifacts[params_.warm_start_artifact]
                           : Json(nullptr);
    input.source_trial = in.value("trial_index", std::uint64_t{0});
    inputs_.push_back(std::move(input));
  }
}

std::vector<Proposal> NovelPolicySeeking::ask(std::size_t n) {
  std::vector<Proposal> out;
  for (std::size_t i = 0; i < inputs_.size() && out.size() < n; ++i) {
    Input& in = inputs_[i];
    if (in.busy || in.asked >= params_.trials_per_input) continue;
    Proposal p;
    p.id = next_id_++;
    p.x = in.x;
    p.context = {{"novelty", {{"features", in.found}, {"d_threshold", params_.d_threshold}}}, {"warm_start", in.warm_start}};
    p.info = {{"source_trial", in.source_trial}, {"iteration", in.asked}};
    p.input = i;
    ++in.asked;
    in.busy = true;
    pending_[p.id] = i;
    out.push_back(std::move(p));
  }
  return out;
}

void NovelPolicySeeking::tell(const std::vector<Observation>& observations) {
  for (const auto& o : observations) {
    auto it = pending_.find(o.id);
    if (it == pending_.end())
      throw UserError(name() + ": tell() got id " + std::to_string(o.id) +
                      ", which is not a pending proposal (never asked or already told)");
    Input& in = inputs_[it->second];
    if (o.ok) {
      if (o.features.size() != features_.size())
        throw UserError(name() + ": trial " + std::to_string(o.id) + " reported " + std::to_string(o.features.size()) +
                        " feature values but the task declares " + std::to_string(features_.size()));
      in.found.push_back(o.features);
    }
    in.busy = false;
    pending_.erase(it);
  }
}

Json NovelPolicySeeking::save() const {
  Json inputs = Json::array(), pending = Json::array();
  for (const auto& in : inputs_) inputs.push_back({{"found", in.found}, {"asked", in.asked}, {"busy", in.busy}});
  for (const auto& [id, i] : pending_) pending.push_back({id, i});
  return {{"next_id", next_id_}, {"inputs", inputs}, {"pending", pending}};
}

void NovelPolicySeeking::load(const Json& state) {
  next_id_ = state.at("next_id").get<std::uint64_t>();
  const Json& inputs = state.at("inputs");
  if (inputs.size() != inputs_.size())
    throw UserError(name() + ": saved state has " + std::to_string(inputs.size()) + " inputs but the stage has " +
                    std::to_string(inputs_.size()));
  for (std::size_t i = 0; i < inputs_.size(); ++i) {
    inputs_[i].found = inputs[i].at("found").get<std::vector<std::vector<double>>>();
    inputs_[i].asked = inputs[i].at("asked").get<int>();
    inputs_[i].busy = inputs[i].at("busy").get<bool>();
  }
  pending_.clear();
  for (const auto& p : state.at("pending")) pending_[p.at(0).get<std::uint64_t>()] = p.at(1).get<std::size_t>();
}

}  // namespace podium::search
