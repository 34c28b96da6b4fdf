#pragma once
/// Evaluation jumps of a policy from the trial's take-off state (§3.6.1's rules): the
/// deterministic jump (the policy mean), whose crossing gives the strategy feature, then
/// `jumps − 1` more with Gaussian action noise. The take-off state is fixed, so a deterministic
/// policy would jump the same way every time; the noise (σ = 0.1 of the action box, the
/// thesis's end-of-anneal σ, §3.4.1) makes the success rate say how robust the jump is.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>

#include "jump_env.h"
#include "podium/character/evaluator.h"

namespace podium::tasks::jump {

struct EvaluationJumps {
  int jumps = 5;           ///< ≥ 1; the first is deterministic
  double sigma = 0.1;      ///< action noise of the others, in half-widths of the action box
  std::uint64_t seed = 1;  ///< the noise's generator (the same for every trial)
};

struct JumpEvaluation {
  double success_rate = 0.0;  ///< over all jumps
  bool deterministic_success = false;
  double return_mean = 0.0;     ///< mean episode reward (eq. 3.16's product, 0 for a failure)
  double mean_offset_l1 = 0.0;  ///< mean over the jumps of the episode-mean L1 offset, rad
  /// The deterministic jump's crossing: Stage 1's up-angle (rad), Stage 2's bar-frame rotation.
  double up_angle_rad = 0.0;
  Eigen::Vector3d bar_rotation = Eigen::Vector3d::Zero();
  bool crossed = false;
  std::filesystem::path trajectory;  ///< the deterministic jump's motion (props included), if recorded
};

/// Runs the jumps on `env` at its current z; with `record_dir` set, writes the deterministic
/// jump's motion there (sim::write_trajectory: the bar, box and block are the World's props, with
/// their kinds; frames at ≥ 60 Hz of simulated time, character::EvaluationConfig::record_min_hz).
JumpEvaluation evaluate_jumps(JumpEnv& env, const character::PolicyFn& policy, const EvaluationJumps& config,
                              const std::filesystem::path& record_dir = {});

}  // namespace podium::tasks::jump
