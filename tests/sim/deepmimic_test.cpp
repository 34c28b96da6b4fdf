// DeepMimic character format (tested on ../shared/data when present; its motion clips are tested
// in tests/character).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "podium/sim/model.h"

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

}  // namespace
}  // namespace podium::sim
