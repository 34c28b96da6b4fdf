#pragma once
/// Motion clips: sequences of poses (nq) for kinematic replay, imitation and retiming.
#include <filesystem>
#include <vector>

#include "podium/sim/model.h"

namespace podium::sim {

struct MotionClip {
  std::vector<double> frame_dt_s;      // duration of each frame, s
  std::vector<Eigen::VectorXd> poses;  // q per frame (nq), z-up
};

/// Reads a DeepMimic motion file (`Frames`: dt, root pos, root quat wxyz, joint quats/angles)
/// for a model loaded by load_deepmimic, converting y-up to z-up.
MotionClip load_deepmimic_motion(const CharacterModel& model, const std::filesystem::path& path);

}  // namespace podium::sim
