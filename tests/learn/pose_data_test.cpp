#include "podium/learn/pose_data.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace podium::learn
