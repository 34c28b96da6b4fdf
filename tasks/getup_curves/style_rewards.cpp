#include "style_rewards.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/character/rewards.h"

namespace podium::tasks::getup_curves {

double height_reward(double h, double target_h) { return std::exp(-1.7 * std::abs(h - target_h)); }  // eq. 5

double torso_reward(double theta_x, double theta_z, double target_x, double target_z) {  // eq. 6
  return std::exp(-1.5 * (std::abs(theta_x - target_x) + std::abs(theta_z - target_z)));
}

double standing_phase(double target_h, double final_target_h) {  // eq. 8
  const double phi = final_target_h > 0.0 ? std::clamp(target_h / final_target_h, 0.0, 1.0) : 1.0;
  return std::exp(-20.0 * (1.0 - phi));
}

double velocity_reward(double alpha, double angular_speed_norm) {  // eq. 7
  return (1.0 - alpha) + alpha * std::exp(-0.05 * angular_speed_norm);
}

double pose_reward(double alpha, double rotation_distance_sum) {  // eq. 9
  return (1.0 - alpha) + alpha * std::exp(-0.1 * rotation_distance_sum);
}

double joint_rotation_distance(const sim::CharacterModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& neutral) {
  double sum = 0.0;
  for (const sim::Link& l : model.links()) {
    if (l.joint == sim::JointType::free) continue;
    if (l.joint == sim::JointType::revolute) {
      sum += std::abs(q(l.q_index) - neutral(l.q_index));
      continue;
    }
    const Eigen::Quaterniond rel = character::quat_at(neutral, l.q_index).conjugate() * character::quat_at(q, l.q_index);
    sum += character::log_map(rel.normalized()).norm();
  }
  return sum;
}

StyleRewardTerms style_rewards(const StyleRewardInput& in) {
  StyleRewardTerms r;
  r.height = height_reward(in.achieved(0), in.target(0));
  r.torso = torso_reward(in.achieved(1), in.achieved(2), in.target(1), in.target(2));
  r.alpha = standing_phase(in.target(0), in.final_target_h);
  r.velocity = velocity_reward(r.alpha, in.angular_speed_norm);
  r.pose = pose_reward(r.alpha, in.rotation_distance_sum);
  r.task = r.height * r.torso * r.velocity * r.pose;                                   // eq. 4
  r.natural = character::naturalness_reward_from_norm(in.offset_l1, in.offset_scale);  // eq. 3
  r.total = r.task * r.natural;                                                        // eq. 2
  return r;
}

ActionFilter::ActionFilter(Eigen::Index size, double beta) : beta_(beta), y_(Eigen::VectorXd::Zero(size)) {
  if (!(beta > 0.0 && beta <= 1.0)) throw base::UserError("action filter: beta " + std::to_string(beta) + " is not in (0, 1]");
}

const Eigen::VectorXd& ActionFilter::step(const Eigen::VectorXd& action) {
  PODIUM_CHECK(action.size() == y_.size(), "action filter: action of the wrong size");
  y_ = beta_ * action + (1.0 - beta_) * y_;  // §3.4
  return y_;
}

void ActionFilter::set_value(const Eigen::VectorXd& y) {
  PODIUM_CHECK(y.size() == y_.size(), "action filter: state of the wrong size");
  y_ = y;
}

EarlyTermination::EarlyTermination(double control_dt_s, double sustain_s, double task_reward_floor) : floor_(task_reward_floor) {
  if (!(control_dt_s > 0.0) || !(sustain_s >= 0.0))
    throw base::UserError("early termination: control step " + std::to_string(control_dt_s) + " s or sustain " +
                          std::to_string(sustain_s) + " s is not positive");
  // "Sustained for more than 300 ms" (§5.3): the first whole number of steps lasting longer; the
  // tolerance keeps 0.3 s / (1/30 s) = 9 steps at exactly 300 ms, not more.
  limit_ = static_cast<int>(std::floor(sustain_s / control_dt_s + 1e-9)) + 1;
}

bool EarlyTermination::step(double task_reward, bool head_on_ground) {
  low_steps_ = task_reward < floor_ ? low_steps_ + 1 : 0;
  head_steps_ = head_on_ground ? head_steps_ + 1 : 0;
  return low_steps_ >= limit_ || head_steps_ >= limit_;
}

void EarlyTermination::restore(int low_reward_steps, int head_down_steps) {
  if (low_reward_steps < 0 || head_down_steps < 0)
    throw base::UserError("early termination: run lengths " + std::to_string(low_reward_steps) + ", " +
                          std::to_string(head_down_steps) + " are not ≥ 0");
  low_steps_ = low_reward_steps;
  head_steps_ = head_down_steps;
}

}  // namespace podium::tasks::getup_curves
