#pragma once
/// The Slower stage's environment (get-up seed §6, Algorithm 2, App. B.2–B.3, D): π_slow tracks a
/// slowed copy of π_weak's own get-up, then holds a standing pose.
///
/// Each episode: a fresh fall in a teacher GetupEnv at π_weak's strength; π_weak (frozen) runs
/// from it until one step after the head origin passes `reference_end_m` (τ_fast, T control steps; capped, and a
/// policy that never rises throws); κ ~ U(κ_low, κ_high) (or the fixed κ of a test); τ_slow =
/// τ_fast retimed by κ (character::retime: T/κ long, through every frame of τ_fast), the standing
/// pose q̂ appended. The episode starts at τ_slow's first state (the fall's end) with probability
/// ε, else at a uniform control step of τ_slow (ε-RSI, §6). Actions are residual PD targets on
/// the reference (k_p = the torque limit, k_d = k_p/10, App. D; k_p/5 while standing, the seed
/// repository's); the state is s_weak without β
/// plus ŝ' = [q, h_com, o_torso] of τ_slow at t+1 and t+5 (§6; the standing pose's after the
/// rise). Reward R_slow while t < T/κ, terminated when h_com is more than 0.5 m off the
/// reference; then R_balance for `balance_steps`, terminated when h_com < 0.5 m (§6).
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "getup_env.h"
#include "podium/character/motion.h"
#include "podium/learn/frozen_policy.h"

namespace podium::tasks::getup {

/// The seed repository's standing pose (env.py STANDING_POSE, MuJoCo humanoid qpos order mapped to
/// humanoid21's joints, whose axes are the same): knees −0.40, ankles −0.30, abdomen −0.12,
/// elbows −1.58 rad.
std::vector<std::pair<std::string, double>> seed_standing_pose();

struct SlowerSettings {
  double kappa_low = 0.2, kappa_high = 0.8;  ///< App. D: κ ~ U(0.2, 0.8)
  /// ε of ε-RSI: the probability of starting at τ_slow's beginning (the seed repository: 0.2).
  double rsi_epsilon = 0.2;
  /// Residual bound, rad per joint (the seed repository adds actions in [−1, 1] to the reference).
  double residual_bound_rad = 1.0;
  /// The standing phase's control steps (the seed repository's env.py _done: 150; §6's text: 100).
  int balance_steps = 150;
  double rise_height_m = 1.2;  ///< §6: standing means the head top above it
  /// τ_fast ends `reference_end_extra_steps` after its first frame with the head *origin* above
  /// this height (the seed repository's env.py run_one_episode: 1.4 m, then one more step).
  double reference_end_m = 1.4;
  int reference_end_extra_steps = 1;
  /// π_slow's simulation rate (the seed repository's humanoid_high_freq.xml: timestep 0.00125).
  double sim_hz = 800.0;
  /// q̂, the standing phase's PD target and R_balance's pose (joint name → rad; joints a variant
  /// removes are skipped), and h'_com there (env.py COM_HEIGHT: 0.80326 m).
  std::vector<std::pair<std::string, double>> standing_pose = seed_standing_pose();
  double standing_com_m = 0.80326;
  /// false: the model's own standing pose (every joint at 0) and its COM height, observed, in
  /// place of standing_pose and standing_com_m (what the shipped π_slow trained with).
  bool seed_standing = true;
  /// PD gains k_p = torque limit and k_d = k_p / ratio: over the rise (App. D and env.py: 10) and
  /// while standing (env.py substep: 5).
  double rise_kd_ratio = 10.0, standing_kd_ratio = 5.0;
  int max_rise_steps = 250;  ///< τ_fast's cap (a Weaker episode's length)
  /// Falls tried per episode before π_weak is declared unable. Every episode needs a rise, so a
  /// π_weak rising from a share p of falls fails a trial of E episodes with probability about
  /// E·(1 − p)^attempts: at 10, the shipped π_weak (p ≈ 0.4, thousands of episodes) failed every
  /// Slower trial within its first 20,000 steps (measured); at 100 that is ≈ 10⁻¹⁹, and
  /// a π_weak that never rises costs 100 × max_rise_steps control steps before it is refused.
  int rise_attempts = 100;
  double track_limit_m = 0.5;  ///< §6: |h_com − h'_com| above it ends the episode
  double fall_limit_m = 0.5;   ///< §6: h_com below it ends the standing phase
};

/// τ_fast at the control rate: frame 0 is the fall's end, frame T the first with the head up.
struct FastRollout {
  std::vector<Eigen::VectorXd> q, qd;
  std::vector<double> com_height_m;
  std::vector<Eigen::Vector3d> torso_up;                        ///< z components of the torso's axes (o_torso)
  int steps() const { return static_cast<int>(q.size()) - 1; }  ///< T
  base::Json to_json() const;
  static FastRollout from_json(const base::Json& json);
};

/// What the env tracks at slow time t: τ_slow's pose, COM height, torso axes and hip velocities;
/// q̂ and its values after the rise.
class SlowReference {
 public:
  SlowReference(FastRollout fast, double kappa, double control_dt_s, const sim::ModelPtr& model,
                const Eigen::VectorXd& standing_q, double standing_com_m);
  double kappa() const { return kappa_; }
  double rise_s() const { return rise_s_; }  ///< T·dt/κ
  /// Whole control steps in the rise, ⌊T/κ⌋ (ε-RSI draws its start among them; tracked_fraction counts them).
  std::int64_t rise_steps() const { return static_cast<std::int64_t>(std::floor(rise_s_ / dt_ + 1e-9)); }
  const FastRollout& fast() const { return fast_; }
  const std::shared_ptr<const character::Clip>& clip() const { return clip_; }  ///< τ_slow then q̂
  double com_height_m(double t_s) const;
  Eigen::Vector3d torso_up(double t_s) const;
  /// The hips' y-joint velocities (right, left) of τ_slow: κ times τ_fast's.
  Eigen::Vector2d hip_velocity(double t_s) const;
  /// The state of τ_slow at t (velocities κ·q̇ of τ_fast).
  std::pair<Eigen::VectorXd, Eigen::VectorXd> state(double t_s) const;

 private:
  double fast_index(double t_s) const;  // τ_fast's fractional frame at slow time t
  FastRollout fast_;
  double kappa_, dt_, rise_s_, standing_com_;
  std::shared_ptr<const character::Clip> clip_;
  int hip_right_ = -1, hip_left_ = -1;  // velocity indices of the hips' y joints
};

/// ε-RSI (§6): the control step of τ_slow (`rise_steps` long) an episode starts at — its
/// beginning, the fall's end, with probability ε, else uniform in [0, rise_steps).
std::int64_t rsi_start_step(base::Rng& rng, std::int64_t rise_steps, double epsilon);

class SlowerEnv final : public character::CharacterEnv {
 public:
  /// `weak`: π_weak, shared read-only; `weak_strength`: the β it passed at. `fixed_kappa`: tests
  /// at one speed (then every episode starts at the fall's end, ε = 1).
  SlowerEnv(const EnvSettings& env, const SlowerSettings& slower, std::shared_ptr<const learn::FrozenPolicy> weak,
            double weak_strength, std::optional<double> fixed_kappa);

  const SlowReference& reference_motion() const { return *reference_; }
  bool standing_phase() const { return reference_time_s() > reference_->rise_s() + 1e-9; }
  /// Mean |h_com − h'_com| over this episode's rise steps so far (0 before the first).
  double mean_com_error_m() const { return rise_steps_ > 0 ? com_error_sum_ / rise_steps_ : 0.0; }
  /// The share of τ_slow's rise this episode has tracked so far: an episode ended early by the
  /// 0.5 m deviation stops short of 1, so a small mean_com_error_m over a short stretch shows as such.
  double tracked_fraction() const;
  /// h'_com − h_com at the last rise step so far (positive: the character below its reference):
  /// a π_slow that follows the slowed kneel but lags the climb has a small mean error and a large gap here.
  double end_com_gap_m() const { return end_com_gap_m_; }
  WeakState weak() const { return weak_state(*this, readings_); }
  const BodyReadings& readings() const { return readings_; }
  /// Sets the speed of later episodes (tests at several κ); nullopt: sampled.
  void set_fixed_kappa(std::optional<double> kappa) { fixed_kappa_ = kappa; }
  /// Transforms τ_fast before retiming (e.g. §8.3's pause: a frame held for a while); empty: none.
  void set_rollout_edit(std::function<FastRollout(FastRollout)> edit) { edit_ = std::move(edit); }

  /// The episode's start (called by the env's Start part): the fall, τ_fast, κ, τ_slow, ε-RSI.
  void begin_episode(base::Rng& rng);
  /// A control step with the phase's PD gains (rise: k_p/rise_kd_ratio; standing: standing_kd_ratio).
  void step(std::span<const double> action, learn::StepResult& out) override;
  /// q̂ and h'_com of the standing phase (SlowerSettings::standing_pose, standing_com_m).
  const Eigen::VectorXd& standing_pose() const { return standing_q_; }
  double standing_com_m() const { return standing_com_m_; }
  /// Reward and termination of a step (the env's RewardFn); adds to the episode's COM error.
  void score(learn::StepResult& out) const;
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

 private:
  SlowerEnv(const EnvSettings& env, const SlowerSettings& slower, const sim::ModelPtr& model,
            std::shared_ptr<const learn::FrozenPolicy> weak, double weak_strength, std::optional<double> fixed_kappa);
  FastRollout rise(base::Rng& rng);
  void build_reference(FastRollout fast, double kappa);

  SlowerSettings settings_;
  std::shared_ptr<const learn::FrozenPolicy> weak_;
  std::shared_ptr<double> teacher_strength_;
  std::unique_ptr<GetupEnv> teacher_;
  std::optional<double> fixed_kappa_;
  std::function<FastRollout(FastRollout)> edit_;
  BodyReadings readings_;
  Eigen::VectorXd standing_q_;
  double standing_com_m_ = 0.0;
  sim::Gains rise_gains_, standing_gains_;
  std::vector<int> free_joints_;        // q indices of the hinges r_pose compares (locked ones excluded)
  int hip_right_ = -1, hip_left_ = -1;  // q̇ indices of the hips' y joints (r_hip)
  std::unique_ptr<SlowReference> reference_;
  mutable double com_error_sum_ = 0.0;  // the episode's tracking statistics, kept by score()
  mutable int rise_steps_ = 0;
  mutable double end_com_gap_m_ = 0.0;
};

}  // namespace podium::tasks::getup
