#pragma once
/// Pose datasets for the pose VAEs. A pose is a vector of joint DoFs (radians): one angle per
/// revolute joint, an exponential map (3 values) per spherical joint, nothing for fixed joints;
/// the root is not part of a pose. Pose sets made from motion clips (DeepMimic's included) come
/// from character/'s pose bridge (poses_from_clip), which learn/ does not see.
#include <filesystem>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::learn {

struct PoseDataset {
  std::vector<std::string> dof_names;           ///< one per pose entry, e.g. "right_hip_x"
  std::vector<double> lower, upper;             ///< joint limits per entry (rad)
  std::vector<std::string> condition_names;     ///< C-VAE conditions, e.g. "root_height_m"
  std::vector<std::vector<double>> poses;       ///< N × dof_names.size()
  std::vector<std::vector<double>> conditions;  ///< N × condition_names.size() (or empty)

  std::size_t size() const { return poses.size(); }
  /// Appends another dataset with the same DoFs and conditions (UserError otherwise).
  void append(const PoseDataset& other);
};

/// Reads the project's JSON pose-set format ({"dof_names", "lower", "upper", "condition_names",
/// "poses", "conditions"}); errors name the file and the bad entry.
PoseDataset read_pose_dataset(const std::filesystem::path& path);

}  // namespace podium::learn
