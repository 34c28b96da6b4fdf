#include "podium/character/character_env.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "podium/base/error.h"

namespace podium::character {

CharacterEnv::CharacterEnv(CharacterEnvParts parts) : parts_(std::move(parts)) {
  if (!parts_.model) throw base::UserError("character env: no model");
  if (!parts_.action) throw base::UserError("character env: no action map");
  if (!parts_.start) throw base::UserError("character env: no start");
  if (!parts_.reward) throw base::UserError("character env: no reward");
  if (parts_.episode_steps < 1)
    throw base::UserError("character env: episode_steps " + std::to_string(parts_.episode_steps) + " is not ≥ 1");
  world_ = std::make_unique<sim::World>(parts_.model, parts_.world);
  if (world_->model_ptr() != parts_.model)  // the World applied model edits (casts, a removed limb)
    throw base::UserError(
        "character env: the World edits the model; build the parts on sim::edit_model(model, edits) and pass that model");
  action_space_ = parts_.action->space(*parts_.model);
  for (const auto& p : parts_.observation) observation_size_ += p->size(*parts_.model);
  features_ = world_->observe();
}

learn::BoxSpace CharacterEnv::observation_space() const {
  const double inf = std::numeric_limits<double>::infinity();
  return {std::vector<double>(observation_size_, -inf), std::vector<double>(observation_size_, inf)};
}

void CharacterEnv::observe(std::vector<double>& observation) {
  features_ = world_->observe();
  observation.resize(observation_size_);
  std::size_t at = 0;
  for (const auto& p : parts_.observation) {
    const std::size_t n = p->size(*parts_.model);
    p->write(*this, std::span<double>(observation).subspan(at, n));
    at += n;
  }
}

void CharacterEnv::note_start_state(std::span<const double> action) {
  if (!parts_.record_start_transitions) return;
  std::vector<double> observation;
  observe(observation);
  if (start_noted_) {
    learn::StepResult result;
    result.info.assign(parts_.info_names.size(), 0.0);
    result.observation = observation;
    parts_.reward(*this, action, result);
    start_transitions_.push_back({.observation = std::move(start_state_),
                                  .action = std::vector<double>(action.begin(), action.end()),
                                  .reward = result.reward,
                                  .next_observation = observation,
                                  .terminated = result.terminated});
  }
  start_state_ = std::move(observation);
  start_noted_ = true;
}

void CharacterEnv::reset(std::vector<double>& observation) {
  step_ = 0;
  reference_time_s_ = 0.0;
  last_action_.clear();
  start_transitions_.clear();
  start_noted_ = false;
  if (parts_.before_episode) parts_.before_episode(*this, rng_);
  parts_.start->begin(*this, rng_);
  observe(observation);
}

void CharacterEnv::step(std::span<const double> action, learn::StepResult& out) {
  if (action.size() != action_space_.size())
    throw base::UserError("character env: an action of " + std::to_string(action.size()) + " values, the action space has " +
                          std::to_string(action_space_.size()));
  for (std::size_t j = 0; j < action.size(); ++j)
    if (!std::isfinite(action[j]))  // a diverged policy: fail the trial with the reason, not silently
      throw std::runtime_error("character env: action " + std::to_string(j) + " is " + std::to_string(action[j]) +
                               ", not finite (the policy has diverged)");
  last_action_.assign(action.begin(), action.end());
  parts_.action->command(*this, action, command_);
  const sim::StepReport report = world_->control_step(parts_.action->control(), command_);
  ++step_;
  reference_time_s_ += control_dt_s();
  out.info.assign(parts_.info_names.size(), 0.0);
  if (!report.ok) {
    // A blown-up state: end the episode without bootstrapping; its observation is not used.
    out.reward = 0.0;
    out.terminated = true;
    out.truncated = false;
    out.observation.assign(observation_size_, 0.0);
    return;
  }
  observe(out.observation);
  out.terminated = false;
  out.truncated = false;  // a reward may end the episode at a time limit of its own
  parts_.reward(*this, action, out);
  out.truncated = !out.terminated && (out.truncated || step_ >= parts_.episode_steps);
}

std::optional<base::Json> CharacterEnv::save_state() const {
  return base::Json{{"world", world_->snapshot().to_json()},
                    {"step", step_},
                    {"reference_time_s", reference_time_s_},
                    {"last_action", last_action_},
                    {"rng", rng_.save()}};
}

void CharacterEnv::load_state(const base::Json& state) {
  try {
    if (!state.contains("world")) throw base::UserError("character env state: world: missing (the World snapshot of save_state)");
    world_->restore(sim::WorldSnapshot::from_json(state.at("world"), world_->model_ptr()));
    step_ = state.at("step").get<int>();
    reference_time_s_ = state.at("reference_time_s").get<double>();
    last_action_ = state.at("last_action").get<std::vector<double>>();
    rng_.load(state.at("rng").get<std::string>());
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("character env state: ") + e.what());
  }
  features_ = world_->observe();
}

}  // namespace podium::character
