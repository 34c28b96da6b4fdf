#include "podium/sim/starts.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace podium::sim {

Eigen::VectorXd random_pose(const CharacterModel& model, base::Rng& rng, double root_height_m, double max_ball_angle_rad) {
  Eigen::VectorXd q = model.neutral();
  for (const Link& l : model.links()) {
    if (l.joint == JointType::revolute) {
      q(l.q_index) = l.lower < l.upper ? rng.uniform(l.lower, l.upper) : rng.uniform(-1.0, 1.0);
      continue;
    }
    Eigen::Quaterniond r;
    if (l.joint == JointType::free) {
      const double u1 = rng.uniform(), u2 = rng.uniform(0, 2 * std::numbers::pi), u3 = rng.uniform(0, 2 * std::numbers::pi);
      const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
      r = Eigen::Quaterniond(a * std::sin(u2), a * std::cos(u2), b * std::sin(u3),
                             b * std::cos(u3));  // Shoemake's uniform rotation
      q.head<3>() << 0.0, 0.0, root_height_m;
    } else {
      const Eigen::Vector3d axis(rng.normal(), rng.normal(), rng.normal());
      r = Eigen::AngleAxisd(rng.uniform(-max_ball_angle_rad, max_ball_angle_rad), axis.normalized());
    }
    const int i = l.joint == JointType::free ? l.q_index + 3 : l.q_index;
    q.segment<4>(i) << r.w(), r.x(), r.y(), r.z();
  }
  return q;
}

void standing_start(World& world) { world.reset(world.model().standing_pose(), Eigen::VectorXd::Zero(world.model().nv())); }

StepReport ragdoll_start(World& world, base::Rng& rng, const RagdollStart& options, const FallObserver& observer) {
  const CharacterModel& model = world.model();
  Eigen::VectorXd q = random_pose(model, rng, options.drop_height_m);
  if (options.lying != RagdollStart::Lying::any) {
    // Standing, the torso's front is +x; pitching it by ∓90° about y puts the front up (supine)
    // or down (prone), with a little random tilt so that falls differ.
    const double pitch = (options.lying == RagdollStart::Lying::supine ? -0.5 : 0.5) * std::numbers::pi + rng.uniform(-0.2, 0.2);
    const Eigen::Quaterniond r =
        Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(rng.uniform(-0.2, 0.2), Eigen::Vector3d::UnitX());
    q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
  }
  const double yaw = options.random_yaw ? rng.uniform(-std::numbers::pi, std::numbers::pi) : options.yaw_rad;
  if (yaw != 0.0) {
    const Eigen::Quaterniond r =
        Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized();
    q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
  }
  q(0) = options.x_m, q(1) = options.y_m;
  const double ground = world.terrain().height(q(0), q(1));
  q(2) = options.drop_height_m + ground;
  CharacterData scratch(model);
  scratch.q = q;
  forward_kinematics(model, scratch);
  const double low = lowest_geom_point(model, scratch) - ground;
  if (low < 0.05) q(2) += 0.05 - low;
  world.reset(q, Eigen::VectorXd::Zero(model.nv()));
  if (observer) observer(nullptr);
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.nv());
  StepReport report;
  for (int k = 0; k < options.control_steps && report.ok; ++k) {
    for (int i = 6; i < model.nv(); ++i) tau(i) = rng.normal(0.0, options.action_sigma) * model.torque_limits()(i);
    report = world.control_step(Control::torque, tau);
    if (report.ok && observer) observer(&tau);
  }
  return report;
}

}  // namespace podium::sim
