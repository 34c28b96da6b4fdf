#pragma once
/// Pose datasets for the pose VAEs and the DeepMimic motion-clip loader that makes them
/// (format: ../shared/data/README.md). A pose is a vector of joint DoFs (radians): one angle per
/// revolute joint, an exponential map (3 values) per spherical joint, nothing for fixed joints;
/// the root is not part of a pose.
#include <filesystem>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::learn {

struct PoseDataset {
  std::vector<std::string> dof_names;            ///< one per pose entry, e.g. "right_hip_x"
  std::vector<double> lower, upper;              ///< joint limits per entry (rad)
  std::vector<std::string> condition_names;      ///< C-VAE conditions, e.g. "root_height_m"
  std::vector<std::vector<double>> poses;        ///< N × dof_names.size()
  std::vector<std::vector<double>> conditions;   ///< N × condition_names.size() (or empty)

  std::size_t size() const { return poses.size(); }
  /// Appends another dataset with the same DoFs and conditions (UserError otherwise).
  void append(const PoseDataset& other);
};

/// Reads the project's JSON pose-set format ({"dof_names", "lower", "upper", "condition_names",
/// "poses", "conditions"}); errors name the file and the bad entry.
PoseDataset read_pose_dataset(const std::filesystem::path& path);

/// One joint of a DeepMimic character file (Skeleton.Joints[i]).
struct DeepMimicJoint {
  enum class Type { root, spherical, revolute, fixed };
  std::string name;
  Type type = Type::fixed;
  std::vector<double> lower, upper;  ///< LimLow/LimHigh per DoF (3 spherical, 1 revolute)
};
std::vector<DeepMimicJoint> read_deepmimic_character(const std::filesystem::path& path);

/// A DeepMimic motion clip: each frame [dt, root pos 3, root quat (w,x,y,z), joint values...].
struct MotionClip {
  bool loop = false;
  std::vector<std::vector<double>> frames;
};
MotionClip read_motion_clip(const std::filesystem::path& path);

/// Converts every frame of `clip` into a pose (spherical quaternions → exponential maps,
/// clamped to the joint limits) with conditions [root height (m), root pitch, root roll (rad)]:
/// the height and torso-orientation features the C-VAE is conditioned on (curve get-up seed §3.5).
PoseDataset clip_to_poses(const MotionClip& clip, const std::vector<DeepMimicJoint>& joints,
                          const std::string& where = "motion clip");

}  // namespace podium::learn
