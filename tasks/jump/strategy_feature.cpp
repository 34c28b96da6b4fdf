#include "strategy_feature.h"

#include <algorithm>
#include <cmath>

#include "podium/character/frames.h"

namespace podium::tasks::jump {

void CrossingRecorder::reset() {
  seen_ = crossed_ = false;
  last_root_ = root_ = Eigen::Quaterniond::Identity();
}

void CrossingRecorder::observe(const Eigen::Vector3d& com, const Eigen::Quaterniond& root) {
  if (crossed_) return;
  const double s = suite_.signed_distance(com);
  if (seen_ && last_distance_ < 0.0 && s >= 0.0) {
    const double t = -last_distance_ / (s - last_distance_);
    root_ = last_root_.slerp(t, root);
    crossed_ = true;
    return;
  }
  if (!seen_ || std::abs(s) < closest_) closest_ = std::abs(s), root_ = root;
  seen_ = true;
  last_distance_ = s;
  last_root_ = root;
}

double up_angle(const Eigen::Quaterniond& root) {
  const Eigen::Vector3d forward = root * Eigen::Vector3d::UnitX();
  return std::acos(std::clamp(forward.z(), -1.0, 1.0));
}

double CrossingRecorder::up_angle() const { return jump::up_angle(root_); }

Eigen::Vector3d CrossingRecorder::bar_frame_rotation() const { return character::log_map(suite_.bar_frame.conjugate() * root_); }

namespace {

base::Json quat_json(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }
Eigen::Quaterniond json_quat(const base::Json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>(), j.at(3).get<double>()};
}

}  // namespace

base::Json CrossingRecorder::state() const {
  return {{"seen", seen_},
          {"crossed", crossed_},
          {"last_distance", last_distance_},
          {"closest", closest_},
          {"last_root", quat_json(last_root_)},
          {"root", quat_json(root_)}};
}

void CrossingRecorder::load_state(const base::Json& state) {
  seen_ = state.at("seen").get<bool>();
  crossed_ = state.at("crossed").get<bool>();
  last_distance_ = state.at("last_distance").get<double>();
  closest_ = state.at("closest").get<double>();
  last_root_ = json_quat(state.at("last_root"));
  root_ = json_quat(state.at("root"));
}

}  // namespace podium::tasks::jump
