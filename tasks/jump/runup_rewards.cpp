#include "runup_rewards.h"

#include <cmath>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "takeoff.h"

namespace podium::tasks::jump {

RunupTarget runup_target(JumpKind kind, std::span<const double> x) {
  const std::size_t n = takeoff_features(kind).size();
  if (x.size() != n)
    throw base::UserError(std::string("jump run-up: ") + jump_kind_name(kind) + " take-off features are " + std::to_string(n) +
                          " values, got " + std::to_string(x.size()));
  RunupTarget t;
  t.kind = kind;
  if (kind == JumpKind::high_jump) {  // §3.6.1: ω_z fixed at the curved sprint's 3 rad/s (takeoff.h)
    t.root_omega = Eigen::Vector3d(x[1], x[2], kHighJumpTurnRate);
    t.lateral_speed = x[3];
  } else {
    t.root_omega = Eigen::Vector3d(x[0], x[1], x[2]);
  }
  return t;
}

RootMotion root_motion(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const Eigen::Matrix3d R = character::quat_at(q, 3).normalized().toRotationMatrix();
  const Eigen::Matrix3d H = character::heading_rotation(character::heading_yaw(R));
  // sim's root ω and v are in the root frame: to world by R, to the heading frame by Hᵀ.
  return {H.transpose() * R * qd.head<3>(), H.transpose() * R * qd.segment<3>(3)};
}

// §3.6.1 eqs. 3.13 and 3.14 (the thesis's v_z is our v_y: takeoff.h).
double runup_task_reward(const RunupTarget& target, const RootMotion& end) {
  double exponent = (target.root_omega - end.omega).lpNorm<1>() / 3.0;
  if (target.kind == JumpKind::high_jump) {
    const double dv = target.lateral_speed - end.velocity.y();
    exponent += 0.7 * dv * dv;
  }
  return std::exp(-exponent);
}

bool takeoff_reached(const TakeoffCondition& c, double t_s, bool takeoff_foot_down, bool other_foot_down) {
  constexpr double kClockTolerance = 1e-9;  // the reference clock is a sum of control periods
  if (t_s >= c.takeoff_time_s - kClockTolerance) return true;
  return t_s >= c.takeoff_time_s - c.window_s - kClockTolerance && takeoff_foot_down && !other_foot_down;
}

double reference_takeoff_time(const sim::CharacterModel& model, std::span<const double> times_s,
                              std::span<const Eigen::VectorXd> poses, int takeoff_foot) {
  return times_s[takeoff_frame(model, poses, takeoff_foot)];
}

}  // namespace podium::tasks::jump
