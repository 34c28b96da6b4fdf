// DeepMimic character and motion formats (tested on ../shared/data when present).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "podium/sim/dynamics.h"
#include "podium/sim/motion.h"
#include "podium/sim/world.h"

namespace podium::sim {
namespace {

std::filesystem::path deepmimic_dir() {
  const char* shared = std::getenv("PODIUM_SHARED_DIR");
  return shared ? std::filesystem::path(shared) / "data/deepmimic/data" : std::filesystem::path();
}

TEST(DeepMimic, LoadsHumanoidWith34Dofs) {
  const auto dir = deepmimic_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "characters/humanoid3d.txt")) GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR)";
  const ModelPtr model = load_deepmimic(dir / "characters/humanoid3d.txt", dir / "controllers/humanoid3d_ctrl.txt");
  EXPECT_EQ(model->nv(), 34);
  EXPECT_EQ(model->nq(), 7 + 4 * 8 + 4);  // 8 spherical + 4 revolute
  EXPECT_NEAR(model->total_mass(), 45.0, 1e-9);
  EXPECT_EQ(model->kp()(model->links()[model->find_link("chest")].v_index), 1000.0);
}

// Replaying a get-up clip kinematically: the root height follows the clip (z-up = DeepMimic's
// y), and at every frame the body touches the ground (lowest geom within a few cm of z = 0).
TEST(DeepMimic, GetUpClipReplayReproducesRootHeightCurve) {
  const auto dir = deepmimic_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "motions/humanoid3d_getup_faceup.txt")) GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR)";
  const ModelPtr model = load_deepmimic(dir / "characters/humanoid3d.txt", dir / "controllers/humanoid3d_ctrl.txt");
  World world(model, WorldConfig{});
  for (const char* clip_name : {"humanoid3d_getup_faceup.txt", "humanoid3d_getup_facedown.txt"}) {
    const MotionClip clip = load_deepmimic_motion(*model, dir / "motions" / clip_name);
    const base::Json raw = base::read_json_file(dir / "motions" / clip_name);
    ASSERT_GT(clip.poses.size(), 10u);
    double worst_height = 0, lowest = 1e9, highest_low = -1e9;
    for (std::size_t f = 0; f < clip.poses.size(); ++f) {
      world.set_state(clip.poses[f], Eigen::VectorXd::Zero(model->nv()));
      const double clip_root_y = raw["Frames"][f][2].get<double>();
      worst_height = std::max(worst_height, std::abs(world.data().links[0].p.z() - clip_root_y));
      const double low = lowest_geom_point(*model, world.data());
      lowest = std::min(lowest, low);
      highest_low = std::max(highest_low, low);
    }
    std::printf("%s: %zu frames, root height error %.2e m, lowest geom point in [%.3f, %.3f] m\n", clip_name, clip.poses.size(), worst_height, lowest,
                highest_low);
    EXPECT_LE(worst_height, 1e-9);
    // Captured clips sink into the floor by a few centimetres at most.
    EXPECT_GT(lowest, -0.08);
    EXPECT_LT(highest_low, 0.06);
  }
}

}  // namespace
}  // namespace podium::sim
