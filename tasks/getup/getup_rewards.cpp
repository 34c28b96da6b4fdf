#include "getup_rewards.h"

#include <cmath>

#include "podium/base/error.h"
#include "podium/character/rewards.h"

namespace podium::tasks::getup {

using character::kInf;
using character::Sigmoid;
using character::tolerance;
using character::Tolerance;

// Long-tailed, as the seed repository's `_standing` term: App. B calls every term Gaussian, but a
// Gaussian with eq. 5's margin gives a lying head (0.25 m) 0.1^12 ≈ 5e-13, and SAC learned
// nothing from it (quick preset, 300k steps, two seeds: every test return 0.0, the head at
// 0.25 m); the long tail gives it 0.009 and a slope towards standing.
double r_head(double head_height_m) { return tolerance(head_height_m, {1.55, kInf, 0.37, 0.1, Sigmoid::long_tail}); }

double r_straight(double torso_up_z, double com_height_m) {
  if (!(com_height_m > 0.5)) return 1.0;  // eq. 6 applies only once the COM is above 0.5 m
  return tolerance(torso_up_z, {0.9, kInf, 1.9, 0.0, Sigmoid::linear});
}

double r_vcom(const Eigen::Vector2d& com_velocity_xy, double bound) {
  const Tolerance t{-bound, bound, 1.2, 0.1, Sigmoid::gaussian};
  return 0.5 * (tolerance(com_velocity_xy.x(), t) + tolerance(com_velocity_xy.y(), t));
}

// Quadratic, as the seed repository's `_closer_feet` (value 0 at the margin: not Gaussian).
double r_feet(double feet_distance_m) { return tolerance(feet_distance_m, {0.0, 0.9, 0.38, 0.0, Sigmoid::quadratic}); }

double reward_weak(const WeakState& s) {
  return r_head(s.head_height_m) * r_straight(s.torso_up_z, s.com_height_m) * r_vcom(s.com_velocity_xy) *
         r_feet(s.feet_distance_m);
}

double r_com(double com_height_error_m) { return tolerance(com_height_error_m, {0.0, 0.0, 0.5, 0.1, Sigmoid::gaussian}); }

double r_ori(const Eigen::Vector3d& torso_up_error) {
  const Tolerance t{-0.03, 0.03, 0.6, 0.3, Sigmoid::gaussian};
  return tolerance(torso_up_error.x(), t) * tolerance(torso_up_error.y(), t) * tolerance(torso_up_error.z(), t);
}

double r_hip(const Eigen::Vector2d& hip_velocity_error) {
  const Tolerance t{-0.5, 0.5, 1.3, 0.1, Sigmoid::gaussian};
  return 0.5 * (tolerance(hip_velocity_error.x(), t) + tolerance(hip_velocity_error.y(), t));
}

double reward_slow(const SlowState& s) {
  return r_com(s.com_height_error_m) * r_ori(s.torso_up_error) * (r_hip(s.hip_velocity_error) + 2.0) / 3.0;
}

double r_pose(double pose_squared_error) { return character::exp_kernel(pose_squared_error, 0.25); }

double reward_balance(const BalanceState& s) {
  return r_vcom(s.com_velocity_xy, 0.0) * r_straight(s.torso_up_z, s.com_height_m) * r_com(s.com_height_error_m) *
         r_pose(s.pose_squared_error);
}

BodyReadings BodyReadings::of(const sim::CharacterModel& model) {
  BodyReadings r;
  const int head = model.head_body();
  const sim::Body& body = model.bodies()[static_cast<std::size_t>(head)];
  bool found = false;
  for (const auto& g : model.links()[static_cast<std::size_t>(body.link)].geoms)
    if (g.body == head && g.type == sim::ShapeType::sphere && (g.pos - body.offset).norm() < 1e-9) {
      r.head_top_m = g.radius;
      found = true;
    }
  if (!found)
    throw base::UserError("getup: the head body " + body.name + " of model " + model.name() +
                          " is not a sphere centred at its origin; the head-top height needs one");
  const auto& effectors = model.end_effector_bodies();
  for (std::size_t i = 0; i < effectors.size(); ++i) {
    const std::string& name = model.bodies()[static_cast<std::size_t>(effectors[i])].name;
    if (name == "foot_left") r.left_foot = static_cast<int>(i);
    if (name == "foot_right") r.right_foot = static_cast<int>(i);
  }
  if (r.left_foot < 0 || r.right_foot < 0)
    throw base::UserError("getup: model " + model.name() + " has no end effectors foot_left and foot_right (r_feet, eq. 8)");
  return r;
}

WeakState weak_state(const character::CharacterEnv& env, const BodyReadings& readings) {
  const sim::Observation& f = env.features();
  const Eigen::Quaterniond root(f.root_quat(0), f.root_quat(1), f.root_quat(2), f.root_quat(3));
  // End effectors are in the root frame: turn their difference back to the world, then drop z.
  const Eigen::Vector3d feet = root * (f.end_effectors[static_cast<std::size_t>(readings.left_foot)] -
                                       f.end_effectors[static_cast<std::size_t>(readings.right_foot)]);
  WeakState s;
  s.head_height_m = f.head_height_m + readings.head_top_m;
  s.com_height_m = f.com.z();
  s.com_velocity_xy = f.com_vel.head<2>();
  s.torso_up_z = f.torso_up.z();
  s.feet_distance_m = feet.head<2>().norm();
  return s;
}

}  // namespace podium::tasks::getup
