#include "jump_evaluation.h"

#include <algorithm>

#include "podium/base/error.h"
#include "podium/base/rng.h"

namespace podium::tasks::jump {

namespace {

const JumpEnv& as_jump(const character::CharacterEnv& env) { return static_cast<const JumpEnv&>(env); }

}  // namespace

JumpEvaluation evaluate_jumps(JumpEnv& env, const character::PolicyFn& policy, const EvaluationJumps& config,
                              const std::filesystem::path& record_dir) {
  if (config.jumps < 1) throw base::UserError("jump evaluation: jumps " + std::to_string(config.jumps) + " is not ≥ 1");
  const learn::BoxSpace box = env.action_space();
  character::EvaluationConfig c;
  for (int k = 0; k < config.jumps; ++k) c.start_seeds.push_back(base::derive_seed(config.seed, static_cast<std::uint64_t>(k)));
  // The jump under way and its noise, restarted at each reset (each_step sees step 0 first).
  std::size_t jump = 0;
  base::Rng noise(0);
  c.each_step = [&](std::size_t start, const character::CharacterEnv& e) {
    if (e.step_index() == 0) jump = start, noise = base::Rng(c.start_seeds[start]);
  };
  const auto act = [&](std::span<const double> observation, std::span<double> action) {
    policy(observation, action);
    if (jump == 0) return;
    for (std::size_t j = 0; j < action.size(); ++j) {
      const double half = 0.5 * (box.high[j] - box.low[j]);
      action[j] = std::clamp(action[j] + config.sigma * half * noise.normal(), box.low[j], box.high[j]);
    }
  };
  c.success = [](const character::CharacterEnv& e) { return as_jump(e).outcome() == Outcome::success; };
  c.measures = {{"offset_l1", [](const character::CharacterEnv& e) { return as_jump(e).sums().mean_offset_l1(); }},
                {"up_angle", [](const character::CharacterEnv& e) { return as_jump(e).crossing().up_angle(); }},
                {"crossed", [](const character::CharacterEnv& e) { return as_jump(e).crossing().crossed() ? 1.0 : 0.0; }}};
  for (int axis = 0; axis < 3; ++axis)
    c.measures.push_back({"rotation_" + std::to_string(axis),
                          [axis](const character::CharacterEnv& e) { return as_jump(e).crossing().bar_frame_rotation()(axis); }});
  // A jump lasts about a second at 10–30 Hz control: the replay takes the simulation's states at
  // ≥ 60 Hz (the measures above still read the control steps only).
  if (!record_dir.empty()) c.record = {0}, c.record_dir = record_dir, c.record_min_hz = 60.0;

  const character::EvaluationReport report = character::evaluate(env, act, c);
  JumpEvaluation out;
  out.success_rate = report.success_rate;
  out.deterministic_success = report.successes.at(0) != 0;
  out.return_mean = report.mean_return;
  out.mean_offset_l1 = report.mean("offset_l1");
  out.up_angle_rad = report.measures.at("up_angle").at(0);
  out.crossed = report.measures.at("crossed").at(0) != 0.0;
  for (int axis = 0; axis < 3; ++axis) out.bar_rotation(axis) = report.measures.at("rotation_" + std::to_string(axis)).at(0);
  if (!report.trajectories.empty()) out.trajectory = report.trajectories.front();
  return out;
}

}  // namespace podium::tasks::jump
