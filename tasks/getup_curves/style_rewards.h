#pragma once
/// The style-curve get-up's rewards, action filter and early termination as pure parts (curve
/// get-up seed §3.4, §5.1, §5.3); curve_env.h feeds them.
#include <Eigen/Core>

#include "podium/sim/model.h"
#include "style_features.h"

namespace podium::tasks::getup_curves {

/// Eq. 5: r_h = exp(−1.7 |h − p_h(s)|), h in m.
double height_reward(double h, double target_h);
/// Eq. 6: r_θ = exp(−1.5 (|θ_x − p_θx(s)| + |θ_z − p_θz(s)|)), angles in rad.
double torso_reward(double theta_x, double theta_z, double target_x, double target_z);
/// Eq. 8: α = exp(−20 (1 − φ)), φ = p_h(s) / p_h(1); φ is clamped to [0, 1] (a curve that
/// overshoots its final height would otherwise give α > 1 and a negative r_v, r_p).
double standing_phase(double target_h, double final_target_h);
/// Eq. 7: r_v = (1 − α) + α exp(−0.05 ‖ω‖), ‖ω‖ the norm of all links' angular velocities (rad/s).
double velocity_reward(double alpha, double angular_speed_norm);
/// Eq. 9: r_p = (1 − α) + α exp(−0.1 Σ_j |log(q̂_j⁻¹ q_j)|), the sum of joint_rotation_distance.
double pose_reward(double alpha, double rotation_distance_sum);
/// Σ_j over the non-root joints of the angle (rad) of q̂_j⁻¹ q_j: a ball joint's relative rotation
/// angle (the norm of its rotation vector, in [0, π]), a hinge's |Δangle|. Both configurations nq.
double joint_rotation_distance(const sim::CharacterModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& neutral);

/// What the rewards of one control step are computed from.
struct StyleRewardInput {
  StyleFeatures achieved = StyleFeatures::Zero();  ///< w = (h, θ_x, θ_z) now
  StyleFeatures target = StyleFeatures::Zero();    ///< p(s) now
  double final_target_h = 1.0;                     ///< p_h(1)
  double angular_speed_norm = 0.0;                 ///< ‖ω‖
  double rotation_distance_sum = 0.0;              ///< joint_rotation_distance to the neutral standing pose
  double offset_l1 = 0.0;                          ///< ‖Δq‖₁ of the filtered action's offsets
  double offset_scale = 10.0;                      ///< c of eq. 3
};
struct StyleRewardTerms {
  double height = 0, torso = 0, alpha = 0, velocity = 0, pose = 0;
  double task = 0;     ///< eq. 4: r_h r_θ r_v r_p
  double natural = 0;  ///< eq. 3: 1 − clip((‖Δq‖₁ / c)², 0, 1)
  double total = 0;    ///< eq. 2: r_task r_natural
};
StyleRewardTerms style_rewards(const StyleRewardInput& in);

/// §3.4's action filter y_t = β a_t + (1 − β) y_{t−1}, β = 0.2 (from y = 0 after reset).
class ActionFilter {
 public:
  explicit ActionFilter(Eigen::Index size, double beta = 0.2);
  void reset() { y_.setZero(); }
  /// Filters one action (its size as constructed) and returns y_t.
  const Eigen::VectorXd& step(const Eigen::VectorXd& action);
  const Eigen::VectorXd& value() const { return y_; }
  /// For resuming an episode: the filter's state y_{t−1}.
  void set_value(const Eigen::VectorXd& y);

 private:
  double beta_;
  Eigen::VectorXd y_;
};

/// §5.3's early termination: an episode ends once r_task < 0.1, or the head touching the ground,
/// is sustained for more than 300 ms — each condition counted on its own, in control steps
/// (30 Hz: the 10th step in a row ends it, the 9th does not).
class EarlyTermination {
 public:
  explicit EarlyTermination(double control_dt_s, double sustain_s = 0.3, double task_reward_floor = 0.1);
  void reset() { low_steps_ = head_steps_ = 0; }
  /// Counts one control step; true when the episode ends here.
  bool step(double task_reward, bool head_on_ground);
  int low_reward_steps() const { return low_steps_; }
  int head_down_steps() const { return head_steps_; }
  /// For resuming an episode: the two run lengths as low_reward_steps() and head_down_steps() gave them.
  void restore(int low_reward_steps, int head_down_steps);

 private:
  int limit_;  // the first run length longer than sustain_s
  double floor_;
  int low_steps_ = 0, head_steps_ = 0;
};

}  // namespace podium::tasks::getup_curves
