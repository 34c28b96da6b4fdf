#include "jump_rules.h"

#include <cstdio>

#include "podium/base/error.h"

namespace podium::tasks::jump {

const char* outcome_name(Outcome outcome) {
  switch (outcome) {
    case Outcome::in_flight:
      return "in_flight";
    case Outcome::success:
      return "success";
    case Outcome::touched_obstacle:
      return "touched_obstacle";
    case Outcome::touched_ground:
      return "touched_ground";
    case Outcome::timed_out:
      return "timed_out";
  }
  return "?";
}

JumpReferee::JumpReferee(const sim::CharacterModel& model, int takeoff_foot, int obstacle_prop, int block_prop, RulesConfig rules)
    : model_(&model), foot_(takeoff_foot), obstacle_(obstacle_prop), block_(block_prop), rules_(rules) {
  if (takeoff_foot < 0 || takeoff_foot >= static_cast<int>(model.bodies().size()))
    throw base::UserError("jump rules: take-off foot body " + std::to_string(takeoff_foot) + " is not a body of " + model.name());
}

void JumpReferee::reset() {
  outcome_ = Outcome::in_flight;
  reason_.clear();
  head_first_ = false;
}

Outcome JumpReferee::judge(const sim::World& world, const sim::Observation& obs, double time_s) {
  if (outcome_ != Outcome::in_flight) return outcome_;
  const auto name = [&](int body) { return model_->bodies()[body].name; };
  const std::string& obstacle = world.terrain().config().boxes.at(obstacle_).name;
  bool on_block = false, head_on_block = false;
  for (const sim::Contact& c : obs.contacts) {
    if (c.partner == sim::Contact::Partner::prop && c.index == obstacle_) {
      outcome_ = Outcome::touched_obstacle, reason_ = name(c.body) + " touched the " + obstacle;
      return outcome_;
    }
    if (c.partner == sim::Contact::Partner::ground && c.body != foot_) {
      outcome_ = Outcome::touched_ground, reason_ = name(c.body) + " touched the ground";
      return outcome_;
    }
    if (c.partner == sim::Contact::Partner::prop && c.index == block_) {
      on_block = true;
      head_on_block = head_on_block || c.body == model_->head_body();
    }
  }
  if (on_block) {
    bool clear = true;
    for (int b = 0; b < static_cast<int>(model_->bodies().size()) && clear; ++b)
      clear = world.prop_distance(b, obstacle_) >= rules_.clearance_m;
    if (clear) {
      outcome_ = Outcome::success, head_first_ = head_on_block;
      reason_ = head_first_ ? "landed on the block head first" : "landed on the block";
      return outcome_;
    }
  }
  if (time_s >= rules_.time_limit_s - 1e-9) {
    char text[64];
    std::snprintf(text, sizeof text, "no landing %g s after take-off", rules_.time_limit_s);
    outcome_ = Outcome::timed_out, reason_ = text;
  }
  return outcome_;
}

base::Json JumpReferee::state() const {
  return {{"outcome", static_cast<int>(outcome_)}, {"reason", reason_}, {"head_first", head_first_}};
}

void JumpReferee::load_state(const base::Json& state) {
  const int outcome = state.at("outcome").get<int>();
  if (outcome < 0 || outcome > static_cast<int>(Outcome::timed_out))
    throw base::UserError("jump rules state: outcome " + std::to_string(outcome) + " is unknown");
  outcome_ = static_cast<Outcome>(outcome);
  reason_ = state.at("reason").get<std::string>();
  head_first_ = state.at("head_first").get<bool>();
}

}  // namespace podium::tasks::jump
