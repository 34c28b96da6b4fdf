#include "podium/character/starts.h"

#include <algorithm>
#include <cmath>

#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/frames.h"
#include "podium/sim/dynamics.h"

namespace podium::character {

namespace {

// Moves the root to (x, y) and turns the whole configuration by yaw about the vertical.
void place(Eigen::VectorXd& q, const Placement& at) {
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(at.yaw_rad, Eigen::Vector3d::UnitZ()));
  set_quat(q, 3, turn * quat_at(q, 3).normalized());
  q(0) = at.x_m, q(1) = at.y_m;
}

// Raises the root so that the lowest geom is at least `clearance` above the terrain under the root.
void lift_above_ground(const sim::World& world, Eigen::VectorXd& q, double clearance) {
  sim::CharacterData scratch(world.model());
  scratch.q = q;
  sim::forward_kinematics(world.model(), scratch);
  const double low = sim::lowest_geom_point(world.model(), scratch) - world.terrain().height(q(0), q(1));
  if (low < clearance) q(2) += clearance - low;
}

}  // namespace

void StandingStart::begin(CharacterEnv& env, base::Rng&) const {
  Eigen::VectorXd q = env.model().standing_pose();
  place(q, at_);
  q(2) += env.world().terrain().height(q(0), q(1));
  env.world().reset(q, Eigen::VectorXd::Zero(env.model().nv()));
}

void RagdollDrop::begin(CharacterEnv& env, base::Rng& rng) const {
  sim::RagdollStart fall = options_;
  fall.lying = lying_;
  fall.x_m = at_.x_m, fall.y_m = at_.y_m, fall.yaw_rad = at_.yaw_rad;
  fall.random_yaw = random_yaw_;
  if (!env.records_start_transitions()) {
    sim::ragdoll_start(env.world(), rng, fall);  // a non-finite state: the env's first step reports it
    return;
  }
  // Each step a transition under the action TorqueActions maps to its torques.
  if (!dynamic_cast<const TorqueActions*>(&env.action_map()))
    throw base::UserError("character starts: a recorded fall needs torque actions (TorqueActions)");
  const sim::CharacterModel& model = env.model();
  const double strength = env.world().config().strength;
  std::vector<double> action(env.action_space().size(), 0.0);
  sim::ragdoll_start(env.world(), rng, fall, [&](const Eigen::VectorXd* tau) {
    if (!tau) return env.note_start_state({});
    for (int i = 6; i < model.nv(); ++i)
      action[std::size_t(i - 6)] = std::clamp((*tau)(i) / (model.torque_limits()(i) * strength), -1.0, 1.0);
    env.note_start_state(action);
  });
}

void ReferenceStart::begin(CharacterEnv& env, base::Rng& rng) const {
  const Clip* clip = env.reference();
  if (!clip) throw base::UserError("character starts: a reference start needs a reference clip");
  const double t = random_time_ ? rng.uniform(0.0, clip->duration_s()) : time_s_;
  Eigen::VectorXd q = clip->sample(t);
  // Velocities of the frame at or before t.
  const std::size_t f = std::upper_bound(clip->times_s.begin(), clip->times_s.end(), t) - clip->times_s.begin() - 1;
  Eigen::VectorXd qd = clip->velocities()[std::min(f, clip->size() - 1)];
  for (const sim::Link& l : env.model().links()) {
    if (l.joint == sim::JointType::revolute) {
      q(l.q_index) += rng.normal(0.0, noise_);
    } else if (l.joint == sim::JointType::spherical) {
      const Eigen::Vector3d e(rng.normal(0.0, noise_), rng.normal(0.0, noise_), rng.normal(0.0, noise_));
      set_quat(q, l.q_index, quat_at(q, l.q_index).normalized() * exp_map(e));
    }
  }
  lift_above_ground(env.world(), q, 0.0);
  env.world().reset(q, qd);
  env.set_reference_time(t);
}

void StateStart::begin(CharacterEnv& env, base::Rng&) const {
  env.world().reset(q_, qd_);
  env.set_reference_time(reference_time_s_);
}

ChoiceStart::ChoiceStart(std::vector<std::pair<double, std::unique_ptr<Start>>> options) : options_(std::move(options)) {
  for (const auto& [w, s] : options_) {
    if (!(w >= 0) || !s) throw base::UserError("character starts: a choice needs starts with weights ≥ 0");
    total_ += w;
  }
  if (!(total_ > 0)) throw base::UserError("character starts: a choice's weights sum to 0");
}

void ChoiceStart::begin(CharacterEnv& env, base::Rng& rng) const {
  double u = rng.uniform(0.0, total_);
  for (const auto& [w, s] : options_) {
    if (u < w) return s->begin(env, rng);
    u -= w;
  }
  options_.back().second->begin(env, rng);
}

}  // namespace podium::character
