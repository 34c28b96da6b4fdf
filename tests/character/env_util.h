#pragma once
// A small get-up-like CharacterEnv on humanoid21 for the env and evaluator tests.
#include <memory>

#include "podium/character/actions.h"
#include "podium/character/observations.h"
#include "podium/character/starts.h"

namespace podium::character::testing {

/// Short falls (seed §7's protocol with fewer noisy steps) keep the tests fast.
inline sim::RagdollStart short_fall() {
  sim::RagdollStart fall;
  fall.control_steps = 10;
  return fall;
}

/// humanoid21 with torque actions, the s_weak-like parts of the get-up task and reward = head height.
inline CharacterEnvParts getup_like_parts(int episode_steps) {
  CharacterEnvParts parts;
  parts.model = sim::load_shipped_model("humanoid21");
  parts.episode_steps = episode_steps;
  parts.action = std::make_unique<TorqueActions>();
  parts.observation.push_back(std::make_unique<JointAngles>(parts.model));
  parts.observation.push_back(std::make_unique<JointVelocities>());
  parts.observation.push_back(std::make_unique<HeadHeight>());
  parts.observation.push_back(std::make_unique<CenterOfMass>());
  parts.observation.push_back(std::make_unique<EndEffectors>());
  parts.observation.push_back(std::make_unique<TorsoAxes>(true));
  parts.start = std::make_unique<RagdollDrop>(short_fall(), RagdollDrop::Lying::any);
  parts.reward = [](const CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    out.reward = env.features().head_height_m;
  };
  return parts;
}

}  // namespace podium::character::testing
