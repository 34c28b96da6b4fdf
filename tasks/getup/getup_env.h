#pragma once
/// The get-up environment of the Discover and Weaker stages (get-up seed §4–5, §7, App. C–D) on
/// character::CharacterEnv: humanoid21 (or a variant), the ragdoll fall as the start, torque
/// actions, the s_weak observation, R_weak, fixed-length episodes without early termination.
///
/// Strength: each episode draws β̂ = clip(N(β^i, ε), floor, 1) (§5, Algorithm 1; ε read as the
/// standard deviation; the seed repository's env.py sample_power), floor = min_strength during the
/// curriculum and β itself once the curriculum has ended (main.py update_power sets power_end to
/// the last strength passed), and reports it as Env::action_scale(), so SAC acts in [−β̂, β̂] (its
/// squashing β̂·tanh, §5) and stores β̂ with each transition; the torque map then multiplies by
/// the torque limits only (the World's strength stays 1). β^i and the floor are shared by every
/// copy and set by the trial between training chunks.
#include <memory>
#include <string>

#include "getup_rewards.h"
#include "podium/character/character_env.h"
#include "podium/learn/frozen_policy.h"
#include "podium/sim/starts.h"

namespace podium::tasks::getup {

struct EnvSettings {
  /// humanoid21_seed: the seed repository's body (humanoid_static.xml: armature, frictionless
  /// self-contact, with passive_joints its damping and stiffness); humanoid21: the same layout
  /// without armature and with μ = 1 between its own bodies (what the shipped policies trained on).
  std::string model = "humanoid21_seed";
  /// §7's variants: "none", "casts" (left elbow and right knee locked straight) or "missing_arm"
  /// (the seed does not say which arm; the left one, from the upper arm down, is removed).
  std::string variant = "none";
  /// π_weak's simulation rate: the seed repository's humanoid_static.xml (timestep 0.005; App. D's
  /// 800 Hz is its Slower's humanoid_high_freq.xml).
  double sim_hz = 200.0;
  double control_hz = 40.0;  ///< App. D
  int episode_steps = 250;   ///< §7
  /// The fall (§7: 1.5 m, 80 control steps); its actions are zero torques as in the seed
  /// repository's env.py reset (the N(0, 0.1) line is commented out there).
  sim::RagdollStart fall = zero_torque_fall();
  /// The fall's control steps join SAC's replay buffer as transitions (the fall's actions, zero
  /// in the seed's fall, with their R_weak), as the seed repository's env.py reset stores them;
  /// they are not training steps.
  bool fall_transitions = true;
  double strength_sigma = 0.04;  ///< ε of §5
  /// Lower clip of β̂ during the curriculum: the seed repository's power_end (main.py: 0.4).
  double min_strength = 0.4;
  /// The model's passive joint damping and stiffness (humanoid21*: the seed repository's MuJoCo
  /// humanoid's) act on every joint, as they always do in the seed's body.
  bool passive_joints = true;

  static sim::RagdollStart zero_torque_fall() {
    sim::RagdollStart fall;
    fall.action_sigma = 0.0;
    return fall;
  }
};

/// β̂ = clip(N(β, ε), floor, 1): one draw of an episode's strength (env.py sample_power).
double draw_strength(base::Rng& rng, double beta, double sigma, double floor);

/// Appends s_weak's body parts (§7 (1)–(5), App. C; every part facing-invariant): joint angles and
/// velocities with the root's angular and linear velocity (the seed repository's dm_control state
/// has them), head height, COM height and velocity in the heading frame, end effectors in the root
/// frame, the z components of the torso axes. GetupEnv adds β̂; SlowerEnv the reference.
void add_weak_observation(std::vector<std::unique_ptr<character::ObservationPart>>& parts, const sim::ModelPtr& model);

/// Throws UserError ("<who> takes N observations and gives M actions; ...") when `policy` does not
/// fit `env` (a policy trained for another variant or model).
void check_policy_fits(const learn::FrozenPolicy& policy, const learn::Env& env, const std::string& who);

/// Whether the character lies on its back: the torso's front axis pointing up (read at a fall's
/// end, it tells a get-up that needs a sit-up or a roll from one that needs a push-up).
inline bool lies_on_back(const character::CharacterEnv& env) { return env.features().torso_up.x() > 0.0; }

/// The model edits of a variant (empty for "none"). Throws base::UserError on an unknown name.
sim::ModelEdits variant_edits(const std::string& variant);

class GetupEnv final : public character::CharacterEnv {
 public:
  /// `curriculum` holds β^i, `floor` the lower clip of β̂ (null: settings.min_strength). With
  /// `sample_strength` false (evaluation) β̂ = β^i exactly.
  GetupEnv(const EnvSettings& settings, std::shared_ptr<const double> curriculum, bool sample_strength,
           std::shared_ptr<const double> floor = nullptr);

  double action_scale() const override { return strength_; }
  /// β̂ of the current episode.
  double strength() const { return strength_; }
  /// R_weak's inputs for the current state.
  WeakState weak() const { return weak_state(*this, readings_); }
  const BodyReadings& readings() const { return readings_; }
  /// The episode hook: draws β̂ (unless replaying a saved episode start) and notes the generator.
  void begin_episode(base::Rng& rng);

  /// At an episode's first step the state is the generator before the start plus β̂, and loading
  /// it replays the fall: bitwise the same episode, so a checkpoint taken between episodes resumes
  /// exactly. Mid-episode it is CharacterEnv's (q, q̇) state (the same dynamics, not bit for bit).
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

 private:
  GetupEnv(const EnvSettings& settings, const sim::ModelPtr& model, std::shared_ptr<const double> curriculum,
           bool sample_strength, std::shared_ptr<const double> floor);

  std::shared_ptr<const double> curriculum_, floor_;
  bool sample_;
  EnvSettings settings_;
  BodyReadings readings_;
  double strength_ = 1.0;
  std::string start_rng_;  // the generator as the start (the fall) began
  bool replaying_ = false;
};

}  // namespace podium::tasks::getup
