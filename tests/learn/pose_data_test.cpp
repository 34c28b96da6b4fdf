#include "podium/learn/pose_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "podium/base/error.h"

namespace podium::learn {
namespace {

namespace fs = std::filesystem;

TEST(PoseData, ProjectPoseSetLoadsInsideItsLimits) {
  const auto d = read_pose_dataset(fs::path(LEARN_DATA_DIR) / "humanoid21_poses.json");
  ASSERT_EQ(d.dof_names.size(), 21u);
  EXPECT_EQ(d.size(), 1000u);
  ASSERT_EQ(d.conditions.size(), d.size());
  for (const auto& p : d.poses)
    for (std::size_t k = 0; k < p.size(); ++k) {
      EXPECT_GE(p[k], d.lower[k]);
      EXPECT_LE(p[k], d.upper[k]);
    }
}

TEST(PoseData, RejectsPoseOfWrongSizeNamingTheEntry) {
  const fs::path path = fs::temp_directory_path() / "podium_learn_bad_poses.json";
  std::ofstream(path) << R"({"dof_names":["a","b"],"lower":[-1,-1],"upper":[1,1],"poses":[[0,0],[0]]})";
  try {
    read_pose_dataset(path);
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("poses[1] has 1 values, expected 2"), std::string::npos) << e.what();
  }
  fs::remove(path);
}

TEST(PoseData, DeepMimicClipBecomesExpMapPoses) {
  const char* shared = std::getenv("PODIUM_SHARED_DIR");
  const fs::path root = shared ? fs::path(shared) / "data/deepmimic/data" : fs::path();
  if (!shared || !fs::exists(root)) GTEST_SKIP() << "PODIUM_SHARED_DIR/data/deepmimic is absent";
  const auto joints = read_deepmimic_character(root / "characters/humanoid3d.txt");
  const auto clip = read_motion_clip(root / "motions/humanoid3d_getup_faceup.txt");
  const auto d = clip_to_poses(clip, joints);
  // 8 spherical joints × 3 + 4 revolute = 28 internal DoFs (thesis §3.6.2: "28 internal DoFs").
  EXPECT_EQ(d.dof_names.size(), 28u);
  EXPECT_EQ(d.size(), clip.frames.size());
  EXPECT_EQ(d.dof_names[0], "chest_x");
  // The clip gets up from lying on the back: the root rises and the torso turns upright.
  EXPECT_LT(d.conditions.front()[0], 0.3);
  EXPECT_GT(d.conditions.back()[0], 0.7);
  EXPECT_GT(std::abs(d.conditions.front()[1]) + std::abs(d.conditions.front()[2]), 1.0);
  EXPECT_LT(std::abs(d.conditions.back()[1]) + std::abs(d.conditions.back()[2]), 0.5);
  // Knee (revolute) values are copied from the frame.
  const std::size_t knee = 9;  // chest 3, neck 3, right hip 3
  ASSERT_EQ(d.dof_names[knee], "right_knee");
  EXPECT_DOUBLE_EQ(d.poses[0][knee], std::clamp(clip.frames[0][8 + 4 + 4 + 4], -3.14, 0.0));
}

TEST(PoseData, JumpVaeClipsBuildOnePoseSet) {
  const char* shared = std::getenv("PODIUM_SHARED_DIR");
  const fs::path root = shared ? fs::path(shared) / "data/jump/data" : fs::path();
  if (!shared || !fs::exists(root / "vae/txt")) GTEST_SKIP() << "PODIUM_SHARED_DIR/data/jump/data/vae is absent";
  // The thesis's P-VAE training clips (CMU-derived), for the 60 kg jumper.
  const auto joints = read_deepmimic_character(root / "characters/humanoid3d_jumper60kg.txt");
  PoseDataset all;
  std::size_t clips = 0, frames = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root / "vae/txt")) {
    if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
    const auto clip = read_motion_clip(entry.path());
    const auto poses = clip_to_poses(clip, joints, entry.path().string());
    if (clips++ == 0) {
      all = poses;
    } else {
      all.append(poses);
    }
    frames += clip.frames.size();
  }
  std::printf("%zu clips, %zu poses of %zu DoFs\n", clips, all.size(), all.dof_names.size());
  EXPECT_GT(clips, 50u);
  EXPECT_EQ(all.size(), frames);
  EXPECT_EQ(all.dof_names.size(), 28u);
  for (const auto& p : all.poses)
    for (std::size_t k = 0; k < p.size(); ++k) ASSERT_TRUE(p[k] >= all.lower[k] && p[k] <= all.upper[k]);
}

}  // namespace
}  // namespace podium::learn
