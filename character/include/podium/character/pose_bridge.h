#pragma once
/// The bridge between learn/'s VAE poses and sim/'s targets. A pose is the joint part of a
/// configuration as a flat vector (learn/pose_data.h): one angle per hinge, one exponential map
/// (axis·angle, 3 values) per ball joint, in the model's link order; the root is not part of it.
/// sim/ holds ball joints as quaternions in z-up frames; VAEs trained on DeepMimic clips hold
/// their exponential maps in DeepMimic's y-up frames, so the bridge converts in either frame.
/// Pose labels (the C-VAE conditions, curve get-up seed §3.5) come from sim's forward kinematics.
#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "podium/character/motion.h"
#include "podium/learn/pose_data.h"
#include "podium/sim/data.h"
#include "podium/sim/model.h"

namespace podium::character {

class PoseBridge {
 public:
  /// The frame ball-joint exponential maps are written in.
  enum class Frame { z_up, y_up };
  explicit PoseBridge(sim::ModelPtr model, Frame frame = Frame::z_up);

  const sim::CharacterModel& model() const { return *model_; }
  std::size_t size() const { return names_.size(); }
  /// "right_knee" for a hinge, "chest_x", "chest_y", "chest_z" for a ball joint.
  const std::vector<std::string>& dof_names() const { return names_; }
  /// Per entry: the hinge's limits (±π when unlimited), ±π for exponential-map entries.
  const std::vector<double>& lower() const { return lower_; }
  const std::vector<double>& upper() const { return upper_; }

  /// The pose of configuration q (nq). Exact inverse of set_pose up to round-off.
  std::vector<double> pose(const Eigen::VectorXd& q) const;
  /// Writes a pose into the joint entries of q (nq); the root entries are left as they are.
  void set_pose(std::span<const double> pose, Eigen::VectorXd& q) const;
  /// A PD/SPD target (nq) for sim::World: the pose on the model's neutral root.
  Eigen::VectorXd target(std::span<const double> pose) const;

 private:
  sim::ModelPtr model_;
  Frame frame_;
  std::vector<std::string> names_;
  std::vector<double> lower_, upper_;
};

/// Names of pose_labels' entries: {"root_height_m", "torso_tilt_rad", "pelvis_tilt_rad"}.
std::vector<std::string> pose_label_names();
/// C-VAE conditions of a configuration by forward kinematics (curve get-up seed §3.5, §4: the
/// character's height and "the angle between local directions of the upper and lower torso
/// segments and the global vertical direction"): the root origin's height above the flat ground
/// (m), the angle of the torso body's up (+z) axis to the vertical, and the same for the lower
/// torso (the body named "pelvis", else the root). Facing-invariant. `scratch` is overwritten.
std::vector<double> pose_labels(const sim::CharacterModel& model, sim::CharacterData& scratch, const Eigen::VectorXd& q);

/// A clip's frames as a pose set for learn's VAEs, with pose_labels as conditions; hinge
/// values outside their limits are clamped (the VAE decoder's range), so no pose leaves them.
learn::PoseDataset poses_from_clip(const PoseBridge& bridge, const Clip& clip);

}  // namespace podium::character
