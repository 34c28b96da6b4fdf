#include "strategy_features.h"

#include "podium/base/error.h"

namespace podium::tasks::getup {

using base::Json;

Json StrategyFeatures::describe() {
  const auto feature = [](const char* name, double low, double high) {
    return Json{{"name", name}, {"low", low}, {"high", high}, {"metric", "euclidean"}};
  };
  return Json::array({feature("chest_up_at_half_height", -1.0, 1.0), feature("side_lean", -1.0, 1.0),
                      feature("hand_support", 0.0, 1.0), feature("knee_support", 0.0, 1.0)});
}

StrategyRecorder::StrategyRecorder(const sim::CharacterModel& model, double head_top_m, double rise_height_m)
    : head_top_m_(head_top_m), rise_height_m_(rise_height_m) {
  // Bodies a variant removed (the missing arm) are simply absent.
  for (const char* name : {"hand_left", "hand_right", "lower_arm_left", "lower_arm_right"})
    if (const int b = model.find_body(name); b >= 0) hands_.push_back(b);
  for (const char* name : {"shin_left", "shin_right"})
    if (const int b = model.find_body(name); b >= 0) shins_.push_back(b);
  if (hands_.empty() || shins_.empty())
    throw base::UserError("getup strategy features: model " + model.name() + " has no hand/forearm or shin bodies");
}

void StrategyRecorder::observe(const character::CharacterEnv& env) {
  if (risen_) return;
  const sim::Observation& f = env.features();
  const double head = f.head_height_m + head_top_m_;
  last_chest_up_ = f.torso_up.x();
  if (!half_seen_ && head > 0.5 * rise_height_m_) half_seen_ = true, chest_up_at_half_ = last_chest_up_;
  const auto on_ground = [&](const std::vector<int>& bodies) {
    for (int b : bodies)
      if (f.touches(b, sim::Contact::Partner::ground)) return true;
    return false;
  };
  steps_ += 1.0;
  side_sum_ += f.torso_up.y();
  hand_steps_ += on_ground(hands_) ? 1.0 : 0.0;
  knee_steps_ += on_ground(shins_) ? 1.0 : 0.0;
  risen_ = head > rise_height_m_;
}

StrategyFeatures StrategyRecorder::features() const {
  StrategyFeatures out;
  const double n = steps_ > 0 ? steps_ : 1.0;
  out.values = {half_seen_ ? chest_up_at_half_ : last_chest_up_, side_sum_ / n, hand_steps_ / n, knee_steps_ / n};
  return out;
}

StrategyFeatures mean_features(const std::vector<StrategyFeatures>& episodes) {
  if (episodes.empty()) throw base::UserError("getup strategy features: no episodes");
  StrategyFeatures out;
  for (const auto& e : episodes)
    for (std::size_t k = 0; k < StrategyFeatures::size; ++k) out.values[k] += e.values[k] / static_cast<double>(episodes.size());
  return out;
}

}  // namespace podium::tasks::getup
