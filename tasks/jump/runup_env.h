#pragma once
/// The run-up environment (thesis §3.6.1, "Run-up Learning"): the athlete imitates a reference run
/// (character/imitation.h: DeepMimic's terms, RSI, early termination, the phase in the state) and
/// is rewarded for ending at a strategy's take-off state (runup_rewards.h, eqs. 3.13–3.14). The
/// episode ends at the take-off condition (the hand-over to the jump policy), on a fall or a
/// large deviation from the reference.
///
/// Reward per control step: ω_I·r_I (DeepMimic's ω_I = 0.7); at the hand-over, plus ω_G·N·r_G with
/// ω_G = 0.3 and N the control steps of a whole run-up, so that the task term's share of a whole
/// run-up's return is DeepMimic's 0.3 (the thesis gives r_G for the end state only).
///
/// Action: residual targets on the reference (default) or DeepMimic's plain PD targets.
///
/// Observation (facing-invariant, DeepMimic-like): per body its position relative to the root,
/// rotation and velocities in the heading frame (character::LinkStates), the root's height, the
/// reference's phase.
#include <memory>
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "podium/character/character_env.h"
#include "podium/character/imitation.h"
#include "runup_rewards.h"

namespace podium::tasks::jump {

struct RunupSettings {
  JumpKind kind = JumpKind::high_jump;
  std::string model = "athlete";
  std::string takeoff_foot = "right_foot", other_foot = "left_foot";
  /// The reference run (DeepMimic format); the config reads it from runup_motions/runup_motion.
  std::string motion;
  double sim_hz = 600.0;
  double control_hz = 30.0;     ///< DeepMimic's 30 Hz
  double takeoff_time_s = 0.0;  ///< on the reference's clock; 0: reference_takeoff_time
  /// How long before the take-off the run-up begins (its first frame, and RSI's range); 0: the
  /// reference's first frame (the thesis's whole run).
  double lead_s = 0.0;
  double handover_window_s = 0.2;  ///< TakeoffCondition::window_s
  double start_noise_rad = 0.02;   ///< RSI joint noise
  /// The action: "residual" (the reference pose + Δq, |Δq| ≤ offset_bound_rad, as the get-up's
  /// Slower stage: a policy that outputs 0 already follows the run for a while) or "targets"
  /// (DeepMimic's: the PD targets themselves, within the joint limits).
  std::string actions = "residual";
  double offset_bound_rad = 1.0;
  double imitation_weight = 0.7, task_weight = 0.3;  ///< DeepMimic's ω_I, ω_G
  double max_com_deviation_m = 1.0;                  ///< early termination
  std::vector<double> takeoff_features;              ///< the strategy's (takeoff_features(kind)'s order)
  /// Another run-up trial's training.ckpt to train on from (same target and sizes); "": from scratch.
  std::string warm_start;
};

/// Reads the run-up keys (runup_motion, runup_control_hz, runup_takeoff_time_s, runup_lead_s, runup_window_s,
/// runup_start_noise, runup_actions, runup_offset_bound, runup_max_com_deviation_m, runup_warm_start); kind, model, takeoff_foot
/// and sim_hz are the jump's, passed in `jump`.
RunupSettings read_runup_settings(base::ConfigReader& r, const RunupSettings& jump);

/// The reference run on the athlete: read, resampled at the control rate, lowered so that its
/// lowest foot point touches the ground (the captured athlete is taller, thesis Table 3.2).
std::shared_ptr<const character::Clip> load_reference_run(const RunupSettings& s);

class RunupEnv final : public character::CharacterEnv {
 public:
  /// `from_start`: every episode starts at the reference's first frame (evaluation, the full
  /// jump); otherwise RSI over the frames before the take-off.
  RunupEnv(const RunupSettings& settings, std::shared_ptr<const character::Clip> reference, bool from_start);

  void reset(std::vector<double>& observation) override;
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

  const RunupSettings& settings() const { return settings_; }
  const TakeoffCondition& condition() const { return condition_; }
  const RunupTarget& target() const { return target_; }
  /// Control steps of a whole run-up (from its first frame to the take-off time).
  int full_steps() const { return full_steps_; }
  /// The run-up's first frame on the reference's clock (lead_s before the take-off, or 0).
  double start_time_s() const { return start_time_s_; }
  bool handed_over() const { return handed_over_; }
  character::Termination termination() const { return termination_; }
  /// The root motion and r_G at the hand-over (valid once handed_over()).
  const RootMotion& end() const { return end_; }
  double task_reward() const { return task_reward_; }

 private:
  struct Parts;
  RunupEnv(const RunupSettings& settings, Parts parts);
  void on_step(learn::StepResult& out);

  RunupSettings settings_;
  std::shared_ptr<const character::ImitationReference> imitation_;
  character::EarlyTermination early_;
  TakeoffCondition condition_;
  RunupTarget target_;
  int foot_ = -1, other_ = -1, full_steps_ = 0;
  double start_time_s_ = 0.0;
  bool handed_over_ = false;
  character::Termination termination_ = character::Termination::none;
  RootMotion end_;
  double task_reward_ = 0.0;
};

/// StepResult::info of RunupEnv, in order: imitation (r_I), handed_over (0/1), task_reward (r_G at
/// the hand-over, else 0), fell (0/1), deviated (0/1), omega_error_x/y/z and lateral_speed_error
/// (end − target at the hand-over, else 0).
std::vector<std::string> runup_info_names();

}  // namespace podium::tasks::jump
