#pragma once
/// The style-curve get-up's three motion features (curve get-up seed §3.3.1 "w", §4.2, Fig. 4):
///   h   — the vertical distance from the base of the neck to the ground (m); the seed measures
///         it to "the average terrain height computed from the height map", passed here as
///         `ground_z` (0 on flat ground);
///   θ_x — the angle between the torso's side vector and global up (rad, [0, π]): the side
///         vector runs from the left hip joint to the right hip joint (lower torso = the root);
///   θ_z — the angle between the torso's front vector and global up (rad, [0, π]): the front
///         vector is (hips' midpoint → neck base) × side, so it follows the upper torso.
/// Standing gives (neck height, π/2, π/2); lying on the back θ_z = 0, on the front θ_z = π; on
/// the right side θ_x = π. The one implementation behind the state, the rewards, the C-VAE
/// labels and curve extraction. Facing-invariant (only angles to the vertical and heights).
#include <Eigen/Core>
#include <array>
#include <string>

#include "podium/sim/data.h"
#include "podium/sim/model.h"

namespace podium::tasks::getup_curves {

/// The features in curve order: h (m), θ_x (rad), θ_z (rad).
using StyleFeatures = Eigen::Vector3d;
/// Short names in curve order, as curve files spell them: "h", "theta_x", "theta_z".
const std::array<std::string, 3>& style_feature_names();

/// Reads the features of a model with joints named "neck", "right_hip" and "left_hip" (humanoid34
/// and DeepMimic's humanoid3d layout: the height point is the neck joint's anchor, the hips'
/// anchors give the side vector).
class StyleFeatureReader {
 public:
  /// Throws base::UserError naming the model and the missing joint.
  explicit StyleFeatureReader(const sim::CharacterModel& model);
  /// From link frames already placed by sim::forward_kinematics.
  StyleFeatures operator()(const sim::CharacterData& placed, double ground_z = 0.0) const;
  /// Runs forward kinematics of q in `scratch` (overwritten) first.
  StyleFeatures at(const Eigen::VectorXd& q, sim::CharacterData& scratch, double ground_z = 0.0) const;

 private:
  const sim::CharacterModel* model_;
  int neck_ = -1, right_hip_ = -1, left_hip_ = -1;
};

}  // namespace podium::tasks::getup_curves
