#include "runup_rewards.h"

#include <cmath>
#include <limits>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/sim/data.h"
#include "podium/sim/dynamics.h"
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
                              std::span<const Eigen::VectorXd> poses, int takeoff_foot, int other_foot) {
  sim::CharacterData d(model);
  const auto low_point = [&](int body) {
    double low = std::numeric_limits<double>::infinity();
    const sim::Body& b = model.bodies()[static_cast<std::size_t>(body)];
    const sim::LinkData& l = d.links[static_cast<std::size_t>(b.link)];
    for (const sim::Geom& g : model.links()[static_cast<std::size_t>(b.link)].geoms) {
      if (g.body != body) continue;
      const Eigen::Matrix3d Rg = l.R * g.rot.toRotationMatrix();
      double z = (l.p + l.R * g.pos).z();
      if (g.type == sim::ShapeType::sphere) z -= g.radius;
      if (g.type == sim::ShapeType::capsule) z -= std::abs(Rg(2, 2)) * g.half_length + g.radius;
      if (g.type == sim::ShapeType::box) z -= Rg.row(2).cwiseAbs().dot(g.half_extents);
      low = std::min(low, z);
    }
    return low;
  };
  std::vector<double> foot(poses.size()), other(poses.size());
  double ground = std::numeric_limits<double>::infinity();
  std::size_t apex = 0;  // the frame of the highest root: the captured jump's flight
  for (std::size_t f = 0; f < poses.size(); ++f) {
    d.q = poses[f];
    sim::forward_kinematics(model, d);
    foot[f] = low_point(takeoff_foot), other[f] = low_point(other_foot);
    ground = std::min({ground, foot[f], other[f]});
    if (poses[f](2) > poses[apex](2)) apex = f;
  }
  constexpr double kContact = 0.03;  // m above the clip's lowest foot point
  // Before the apex: a captured run-up goes on past its take-off (the curved sprint lands and walks
  // out, its last single support is after the landing), and the run-up ends at the take-off.
  for (std::size_t f = apex + 1; f-- > 0;)
    if (foot[f] - ground < kContact && other[f] - ground >= kContact) return times_s[f];
  throw base::UserError("jump run-up: the reference run never has " +
                        model.bodies()[static_cast<std::size_t>(takeoff_foot)].name + " alone on the ground");
}

}  // namespace podium::tasks::jump
