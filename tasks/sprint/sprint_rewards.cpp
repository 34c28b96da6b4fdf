// The sprint's reward terms (sprint seed §2 "Reward", §3.2).
#include "sprint_rewards.h"

#include <cmath>

#include "podium/character/frames.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::sprint {

double forward_speed(double x_before_m, double x_after_m, double dt_s) { return (x_after_m - x_before_m) / dt_s; }  // §2, r_f

double lateral_penalty(double offset_m, double lane_width_m, double weight) {
  const double r = offset_m / (0.5 * lane_width_m);
  return -weight * r * r;  // §2, r_d
}

BaseReward base_reward(const RewardWeights& w, double x_before_m, double x_after_m, double dt_s, double lateral_offset_m,
                       double lane_width_m, bool fallen) {
  BaseReward r;  // §2: r_base = r_f + r_s + r_d
  r.forward = w.forward * forward_speed(x_before_m, x_after_m, dt_s);
  r.survival = fallen ? 0.0 : w.survival;
  r.lateral = lateral_penalty(lateral_offset_m, lane_width_m, w.lateral);
  return r;
}

Eigen::Vector3d com_in_heading_frame(const sim::CharacterModel& model, sim::CharacterData& data) {
  sim::forward_kinematics(model, data);
  Eigen::Vector3d com, com_vel;
  sim::center_of_mass(model, data, com, com_vel);
  const Eigen::Matrix3d& root = data.links[0].R;
  return character::heading_rotation(character::heading_yaw(root)).transpose() * (com - data.links[0].p);
}

double mass_penalty(const Eigen::Vector3d& com_heading, const Eigen::Vector3d& upright_com_heading, double weight) {
  return -weight * (com_heading - upright_com_heading).norm();  // §3.2, r_mass
}

double sagittal_angle(const sim::CharacterModel& model, const sim::CharacterData& data, int body) {
  const Eigen::Matrix3d& R = data.links[model.bodies().at(body).link].R;
  const Eigen::Matrix3d heading = character::heading_rotation(character::heading_yaw(data.links[0].R));
  const Eigen::Vector3d d = heading.transpose() * (R * -Eigen::Vector3d::UnitZ());
  return std::atan2(d.x(), -d.z());
}

double diagonal_reward(const SwingAngles& s, double k) {
  const double legs = s.left_hip - s.right_hip, arms = s.right_shoulder - s.left_shoulder;
  return std::exp(-k * (legs - arms) * (legs - arms));  // §3.2, the diagonal pattern
}

}  // namespace podium::tasks::sprint
