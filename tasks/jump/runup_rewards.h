#pragma once
/// The run-up's task reward and its hand-over to the jump (thesis §3.6.1, "Run-up Learning"): a
/// run-up policy imitates a reference run (character/imitation.h) and is rewarded for ending at
/// the strategy's take-off state; at the take-off condition the jump policy takes over.
///
/// Eq. 3.13 (high jump): r_G = exp(−⅓‖ω̄ − ω‖₁ − 0.7·(v̄_z − v_z)²), eq. 3.14 (obstacle jump):
/// r_G = exp(−⅓‖ω̄ − ω‖₁); ω is the root's angular velocity and v_z its lateral speed, both in the
/// facing-direction frame, barred: the targets. In our axes (takeoff.h: z up, facing +x, y left)
/// the thesis's v_z is our v_y; the approach angle α is not in the reward (the suite is turned).
#include <Eigen/Core>
#include <span>

#include "jump_schedules.h"
#include "podium/sim/model.h"

namespace podium::tasks::jump {

/// What a strategy's run-up must end at, in the heading frame.
struct RunupTarget {
  JumpKind kind = JumpKind::high_jump;
  Eigen::Vector3d root_omega = Eigen::Vector3d::Zero();  ///< ω̄, rad/s
  double lateral_speed = 0.0;                            ///< v̄_y (high jump only), m/s
};
/// The target of a strategy's take-off features x (takeoff_features(kind)'s order): high jump
/// ω̄ = (x₁, x₂, 3 rad/s), v̄_y = x₃; obstacle ω̄ = x. Throws base::UserError for a wrong size.
RunupTarget runup_target(JumpKind kind, std::span<const double> takeoff_features);

/// The root's angular and linear velocity in the heading frame (frames.h) of a state (q, q̇ in
/// sim's convention).
struct RootMotion {
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};
RootMotion root_motion(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);

/// Eq. 3.13 (high jump) or eq. 3.14 (obstacle) of the run-up's end state: 1 at the target.
double runup_task_reward(const RunupTarget& target, const RootMotion& end);

/// The take-off condition (where the run-up hands over to the jump policy): within `window_s`
/// before the reference run's take-off time, the first control step with the take-off foot alone
/// on the ground; else the step at which the reference clock reaches the take-off time.
struct TakeoffCondition {
  double takeoff_time_s = 0.0;  ///< on the reference run's clock
  double window_s = 0.2;        ///< how early a single-support step may hand over
};
/// Whether the run-up hands over after the control step that ended at reference time `t_s`.
bool takeoff_reached(const TakeoffCondition& condition, double t_s, bool takeoff_foot_down, bool other_foot_down);

/// The reference run's take-off time: its takeoff_frame (takeoff.h), the frame Stage 1 takes a
/// clip's take-off state from.
double reference_takeoff_time(const sim::CharacterModel& model, std::span<const double> times_s,
                              std::span<const Eigen::VectorXd> poses, int takeoff_foot);

}  // namespace podium::tasks::jump
