#include "style_features.h"

#include <algorithm>
#include <cmath>

#include "podium/sim/dynamics.h"

namespace podium::tasks::getup_curves {

namespace {

double angle_to_up(const Eigen::Vector3d& v) {
  const double n = v.norm();
  if (n == 0.0) return std::acos(0.0);  // degenerate (neck on the hip line): call it level
  return std::acos(std::clamp(v.z() / n, -1.0, 1.0));
}

}  // namespace

const std::array<std::string, 3>& style_feature_names() {
  static const std::array<std::string, 3> names{"h", "theta_x", "theta_z"};
  return names;
}

StyleFeatureReader::StyleFeatureReader(const sim::CharacterModel& model) : model_(&model) {
  const auto index = [&](const char* joint) {
    model.link(joint);  // throws base::UserError naming the model and the joint
    return model.find_link(joint);
  };
  neck_ = index("neck");
  right_hip_ = index("right_hip");
  left_hip_ = index("left_hip");
}

// Curve get-up seed §4.2 and Fig. 4: the height point is the neck base; the side vector lies on
// the lower torso (hip to hip), the front vector on the upper torso (hips → neck, crossed with side).
StyleFeatures StyleFeatureReader::operator()(const sim::CharacterData& placed, double ground_z) const {
  const Eigen::Vector3d& neck = placed.links[neck_].p;
  const Eigen::Vector3d& right = placed.links[right_hip_].p;
  const Eigen::Vector3d& left = placed.links[left_hip_].p;
  const Eigen::Vector3d side = right - left;
  const Eigen::Vector3d front = (neck - 0.5 * (right + left)).cross(side);
  return {neck.z() - ground_z, angle_to_up(side), angle_to_up(front)};
}

StyleFeatures StyleFeatureReader::at(const Eigen::VectorXd& q, sim::CharacterData& scratch, double ground_z) const {
  scratch.q = q;
  sim::forward_kinematics(*model_, scratch);
  return (*this)(scratch, ground_z);
}

}  // namespace podium::tasks::getup_curves
