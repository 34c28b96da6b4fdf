#pragma once
/// The high jump and obstacle jump environment (thesis §3.4, §3.6.1) on character::CharacterEnv:
/// the take-off state as the start, the suite's props in the World, composite PD targets (P-VAE
/// latent + per-joint offsets, stable PD by MABA) or plain targets, global-frame observations, the
/// rules judged after every control step, and the sparse reward at the end.
///
/// Observation (§3.4.1, not facing-invariant on purpose): per body its position relative to the
/// root, rotation (two matrix columns), linear and angular velocity, all in world axes
/// (character::LinkStates, Frame::world; 15 per body), then the root's world position (3: the
/// suite is fixed in the world, so this is where the character is relative to the bar) and z (1).
///
/// Difficulty z: the control rate (f_control(ρ)) is fixed when the env is built (the World steps
/// at one rate); set_difficulty moves the props and c_offset at once and says whether the rate
/// still fits, else the trial builds a new env at the new z.
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "jump_rewards.h"
#include "jump_rules.h"
#include "jump_schedules.h"
#include "jump_suite.h"
#include "podium/base/config.h"
#include "podium/character/character_env.h"
#include "podium/character/pose_bridge.h"
#include "podium/learn/vae.h"
#include "strategy_feature.h"
#include "takeoff.h"

namespace podium::tasks::jump {

struct JumpSettings {
  JumpKind kind = JumpKind::high_jump;
  /// sim/models/<model>.json; "athlete" (the thesis's 60 kg jumper, Table 3.2). Its body names must include
  /// takeoff_foot.
  std::string model = "athlete";
  std::string takeoff_foot = "right_foot";  ///< the body allowed on the ground
  double difficulty_m = 0.5;                ///< z: bar height (high jump) or obstacle width
  double sim_hz = 600.0;                    ///< thesis §3.6.2
  /// The reference take-off state: "" the shipped one (shipped_takeoff_path), else a file —
  /// .json (ours), .npy (a captured run-up's end, arpspoof/Jump data/states) or .txt (a captured
  /// jump, DeepMimic format: its take-off frame).
  std::string takeoff_state;
  /// Stage 1's x (takeoff_features(kind)); empty: the reference state as it is, and
  /// layout.approach_angle_rad.
  std::vector<double> takeoff_features;
  SuiteLayout layout;
  RulesConfig rules;
  double latent_bound = 3.0;                            ///< P-VAE latent box ±3σ
  double offset_bound = 2.0;                            ///< per-joint offsets, rad (authors' repository: offset scale 2)
  double novelty_threshold_rad = std::numbers::pi / 2;  ///< d_threshold of eq. 3.12 (§3.6.2: π/2)
  /// The thesis's variations (§3.7, Figs. 3.8–3.9: a weaker take-off leg at 60% torque, an
  /// inflexible spine, a cast knee, a jump on Mars): the jump policy trains on the changed body or
  /// world from the same take-off state. Gravity's magnitude, m/s² (Mars: 3.711).
  double gravity_mps2 = 9.81;
  double strength = 1.0;    ///< every torque limit × this (the World's strength)
  double mass_scale = 1.0;  ///< every body's mass and inertia × this
  /// Per joint, model-file keys merged into its entry (sim::ModelEdits: "lock" for a cast,
  /// "range"/"swing"/"twist" for a stiffer joint, "torque_limit" for a weaker one).
  std::vector<std::pair<std::string, base::Json>> joint_edits;
};

/// Reads JumpSettings' keys (all optional: kind, model, takeoff_foot, difficulty_m (0, the
/// default: Table 3.1's z_min for the kind), sim_hz,
/// takeoff_state, takeoff_features, approach_angle_rad, wall_distance_m, obstacle_distance_m,
/// clearance_m, time_limit_s, latent_bound, offset_bound, novelty_threshold_rad, gravity_mps2,
/// strength, mass_scale, joint_edits) for a plugin's config; errors name the key.
JumpSettings read_jump_settings(base::ConfigReader& r);

/// The model edits of the settings' variations (joint_edits, mass_scale; none by default).
sim::ModelEdits variation_edits(const JumpSettings& s);

/// A trained pose prior for composite targets; without one the env uses plain targets.
struct PosePrior {
  std::shared_ptr<const learn::PoseVae> vae;
  /// The frame the VAE's poses are in (y_up for one trained on DeepMimic-format clips).
  character::PoseBridge::Frame frame = character::PoseBridge::Frame::z_up;
};

class JumpEnv final : public character::CharacterEnv {
 public:
  /// Throws base::UserError for an unknown model, foot, state file or a bad setting.
  explicit JumpEnv(const JumpSettings& settings, PosePrior prior = {});

  void reset(std::vector<double>& observation) override;
  /// CharacterEnv's state (the World snapshot, exact) plus z and the episode's rules, sums and
  /// feature; loads into a JumpEnv of the same settings and control rate (z may differ: it is set
  /// from the state), which then continues the episode bitwise.
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

  const JumpSettings& settings() const { return settings_; }
  double difficulty_m() const { return z_; }
  double c_offset() const { return c_offset_; }
  /// Moves and resizes the props for z (call between episodes); returns false when this env's
  /// control rate is no longer f_control(ρ(z)).
  bool set_difficulty(double z_m);
  /// Stage 2 (eq. 3.12): the bar-frame rotations of the policies already found.
  void set_known_features(std::vector<std::vector<double>> features) { known_ = std::move(features); }

  const JumpSuite& suite() const { return suite_; }
  const TakeoffState& takeoff() const { return takeoff_; }
  int takeoff_foot() const { return foot_; }
  /// The episode so far: outcome and reason (jump_rules.h), the reward terms at its end, and the
  /// strategy feature. A blown-up state ends the episode (CharacterEnv: terminated, reward 0)
  /// with the outcome still in_flight.
  Outcome outcome() const { return referee_.outcome(); }
  const std::string& outcome_reason() const { return referee_.reason(); }
  const RewardTerms& reward_terms() const { return terms_; }
  /// The episode's sums for r_ω and r_naturalness so far (mean root speed, mean L1 offset).
  const EpisodeSums& sums() const { return sums_; }
  const CrossingRecorder& crossing() const { return crossing_; }

 private:
  struct Parts;
  JumpEnv(const JumpSettings& settings, Parts parts);
  void on_step(std::span<const double> action, learn::StepResult& out);
  void observe_crossing();

  JumpSettings settings_;
  TakeoffState takeoff_;
  int foot_ = -1;
  bool composite_ = false;
  std::size_t latent_size_ = 0;
  double z_ = 0.0, c_offset_ = 0.0;
  JumpSuite suite_;
  JumpReferee referee_;
  CrossingRecorder crossing_;
  EpisodeSums sums_;
  RewardTerms terms_;
  std::vector<std::vector<double>> known_;
};

/// StepResult::info of JumpEnv, in order: success (0/1), outcome (Outcome's value: 0 in flight,
/// 1 success, 2 touched_obstacle, 3 touched_ground, 4 timed_out), head_first (0/1), the episode's
/// mean root angular speed (rad/s) and mean L1 offset (rad) so far, the Stage 1 feature (rad), z (m).
std::vector<std::string> jump_info_names();

}  // namespace podium::tasks::jump
