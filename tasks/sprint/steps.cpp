// The sprint's step counter (sprint seed §2 "State": z, the normalised number of alternating steps).
#include "steps.h"

#include <string>

#include "podium/base/error.h"

namespace podium::tasks::sprint {

StepCounter::StepCounter(StepCounterConfig config) : config_(config) {
  if (config_.debounce < 1)
    throw base::UserError("sprint: step counter debounce " + std::to_string(config_.debounce) + " is not ≥ 1");
  if (!(config_.n_norm > 0.0))
    throw base::UserError("sprint: step counter n_norm " + std::to_string(config_.n_norm) + " is not > 0");
}

void StepCounter::reset(bool left_down, bool right_down) {
  feet_[0] = {left_down ? 1 : 0, !left_down};
  feet_[1] = {right_down ? 1 : 0, !right_down};
  steps_ = 0;
  last_.reset();
}

bool StepCounter::touchdown(FootState& foot, bool down) const {
  if (!down) {
    foot.run = 0;
    foot.lifted = true;
    return false;
  }
  ++foot.run;
  if (foot.lifted && foot.run >= config_.debounce) {
    foot.lifted = false;
    return true;
  }
  return false;
}

bool StepCounter::observe(bool left_down, bool right_down) {
  const bool left = touchdown(feet_[0], left_down), right = touchdown(feet_[1], right_down);
  // The foot opposite to the last counted one; a touchdown of the same foot again is not a step.
  std::optional<Foot> counted;
  if (left && last_ != Foot::left) counted = Foot::left;
  else if (right && last_ != Foot::right) counted = Foot::right;
  if (!counted) return false;
  ++steps_;
  last_ = counted;
  return true;
}

base::Json StepCounter::state() const {
  base::Json feet = base::Json::array();
  for (const FootState& f : feet_) feet.push_back({{"run", f.run}, {"lifted", f.lifted}});
  base::Json last = nullptr;
  if (last_) last = *last_ == Foot::left ? "left" : "right";
  return {{"steps", steps_}, {"last", last}, {"feet", feet}};
}

void StepCounter::load_state(const base::Json& state) {
  try {
    steps_ = state.at("steps").get<int>();
    const base::Json& last = state.at("last");
    if (last.is_null()) last_.reset();
    else if (last == "left") last_ = Foot::left;
    else if (last == "right") last_ = Foot::right;
    else throw base::UserError("sprint: step counter state: last: " + last.dump() + " is not left, right or null");
    for (int f = 0; f < 2; ++f) {
      feet_[f].run = state.at("feet").at(f).at("run").get<int>();
      feet_[f].lifted = state.at("feet").at(f).at("lifted").get<bool>();
    }
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("sprint: step counter state: ") + e.what());
  }
}

}  // namespace podium::tasks::sprint
