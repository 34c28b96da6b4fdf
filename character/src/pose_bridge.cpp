#include "podium/character/pose_bridge.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/sim/dynamics.h"

namespace podium::character {

using sim::JointType;
using sim::Link;

PoseBridge::PoseBridge(sim::ModelPtr model, Frame frame) : model_(std::move(model)), frame_(frame) {
  constexpr double pi = std::numbers::pi;
  for (const Link& l : model_->links()) {
    if (l.joint == JointType::revolute) {
      names_.push_back(l.name);
      const bool limited = l.lower < l.upper;
      lower_.push_back(limited ? l.lower : -pi);
      upper_.push_back(limited ? l.upper : pi);
    } else if (l.joint == JointType::spherical) {
      for (const char* axis : {"_x", "_y", "_z"}) {
        names_.push_back(l.name + axis);
        lower_.push_back(-pi);
        upper_.push_back(pi);
      }
    }
  }
}

// Ball rotations change frame as R_z = C R_y Cᵀ (read_deepmimic_clip), so rotation vectors map e_z = C e_y.
std::vector<double> PoseBridge::pose(const Eigen::VectorXd& q) const {
  std::vector<double> out;
  out.reserve(names_.size());
  const Eigen::Quaterniond& c = yup_to_zup();
  for (const Link& l : model_->links()) {
    if (l.joint == JointType::revolute) {
      out.push_back(q(l.q_index));
    } else if (l.joint == JointType::spherical) {
      Eigen::Vector3d e = log_map(quat_at(q, l.q_index));
      if (frame_ == Frame::y_up) e = c.conjugate() * e;
      out.insert(out.end(), e.data(), e.data() + 3);
    }
  }
  return out;
}

void PoseBridge::set_pose(std::span<const double> pose, Eigen::VectorXd& q) const {
  if (pose.size() != names_.size())
    throw base::UserError("pose bridge: a pose of " + std::to_string(pose.size()) + " values for model " + model_->name() +
                          ", which needs " + std::to_string(names_.size()));
  const Eigen::Quaterniond& c = yup_to_zup();
  std::size_t k = 0;
  for (const Link& l : model_->links()) {
    if (l.joint == JointType::revolute) {
      q(l.q_index) = pose[k++];
    } else if (l.joint == JointType::spherical) {
      Eigen::Vector3d e(pose[k], pose[k + 1], pose[k + 2]);
      k += 3;
      if (frame_ == Frame::y_up) e = c * e;
      set_quat(q, l.q_index, exp_map(e));
    }
  }
}

Eigen::VectorXd PoseBridge::target(std::span<const double> pose) const {
  Eigen::VectorXd q = model_->neutral();
  set_pose(pose, q);
  return q;
}

std::vector<std::string> pose_label_names() { return {"root_height_m", "torso_tilt_rad", "pelvis_tilt_rad"}; }

std::vector<double> pose_labels(const sim::CharacterModel& model, sim::CharacterData& scratch, const Eigen::VectorXd& q) {
  scratch.q = q;
  sim::forward_kinematics(model, scratch);
  const auto tilt = [&](int body) {
    const Eigen::Vector3d up = scratch.links[model.bodies()[body].link].R.col(2);
    return std::acos(std::clamp(up.z(), -1.0, 1.0));
  };
  const int pelvis = model.find_body("pelvis");
  return {scratch.links[0].p.z(), tilt(model.torso_body()), tilt(pelvis >= 0 ? pelvis : model.links()[0].body)};
}

learn::PoseDataset poses_from_clip(const PoseBridge& bridge, const Clip& clip) {
  learn::PoseDataset d;
  d.dof_names = bridge.dof_names();
  d.lower = bridge.lower();
  d.upper = bridge.upper();
  d.condition_names = pose_label_names();
  sim::CharacterData scratch(bridge.model());
  for (const Eigen::VectorXd& q : clip.poses) {
    std::vector<double> p = bridge.pose(q);
    for (std::size_t k = 0; k < p.size(); ++k) p[k] = std::clamp(p[k], d.lower[k], d.upper[k]);
    d.poses.push_back(std::move(p));
    d.conditions.push_back(pose_labels(bridge.model(), scratch, q));
  }
  return d;
}

}  // namespace podium::character
