// Terrain height queries agree with what Bullet collides against.
#include <gtest/gtest.h>

#include "podium/base/error.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/starts.h"
#include "podium/sim/terrain.h"
#include "podium/sim/world.h"

namespace podium::sim {
namespace {

TEST(Terrain, RoughTilesAreSeededAndWithinLevel) {
  const Terrain a(TerrainConfig::rough("hard", 7)), b(TerrainConfig::rough("hard", 7)), c(TerrainConfig::rough("hard", 8));
  double max_h = 0;
  bool differs = false;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      EXPECT_EQ(a.tile_height(i, j), b.tile_height(i, j));
      differs |= a.tile_height(i, j) != c.tile_height(i, j);
      max_h = std::max(max_h, a.tile_height(i, j));
    }
  EXPECT_TRUE(differs);
  EXPECT_LE(max_h, 0.2);
  EXPECT_GT(max_h, 0.1);
  EXPECT_THROW(TerrainConfig::rough("steep", 1), base::UserError);
}

TEST(Terrain, HeightMapSeesBoxesAndSlope) {
  TerrainConfig config;
  config.kind = TerrainConfig::Kind::slope;
  config.slope_rad = 0.1;
  config.boxes.push_back(BoxProp{Eigen::Vector3d(2, 0, 0.5), Eigen::Vector3d(0.2, 0.2, 0.5), 0.0, 1.0});
  const Terrain t(config);
  EXPECT_NEAR(t.height(1.0, 3.0), std::tan(0.1), 1e-12);
  EXPECT_NEAR(t.height(2.0, 0.0), 1.0, 1e-12);
  const auto map = t.height_map(1.5, 0.0, 0.0, 0.25, 0.0);  // row a = 4 is x + 0.5 = 2.0
  EXPECT_NEAR(map[4 * 5 + 2], 1.0, 1e-12);
  EXPECT_NEAR(map[0], std::tan(0.1) * 1.0, 1e-12);
}

// A character dropped on rough tiles comes to rest on them, not on the plane below.
TEST(Terrain, RagdollRestsOnRoughTiles) {
  WorldConfig config;
  config.terrain = TerrainConfig::rough("hard", 3);
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, config);
  base::Rng rng(2);
  ASSERT_TRUE(ragdoll_start(world, rng).ok);
  for (int k = 0; k < 40; ++k) world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv()));
  // Lowest body point sits on the terrain below it (within 2 cm), which is above z = 0 there.
  double gap = 1e9;
  for (std::size_t b = 0; b < model->bodies().size(); ++b) {
    const Eigen::Vector3d p = body_point(*model, world.data(), static_cast<int>(b), Eigen::Vector3d::Zero());
    gap = std::min(gap, p.z() - world.terrain().height(p.x(), p.y()));
  }
  EXPECT_GT(gap, -0.02);
  EXPECT_LT(world.observe().head_height_m, 0.5);
}

// A crash mat (box prop) catches the ragdoll: it comes to rest on the mat's top, 0.3 m up.
TEST(Terrain, RagdollLandsOnCrashMat) {
  WorldConfig config;
  config.terrain.boxes.push_back(BoxProp{Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(2.0, 2.0, 0.15), 0.3, 1.0});
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, config);
  base::Rng rng(6);
  RagdollStart start;
  start.drop_height_m = 1.8;
  ASSERT_TRUE(ragdoll_start(world, rng, start).ok);
  const double low = lowest_geom_point(*model, world.data());
  EXPECT_GT(low, 0.28);
  EXPECT_LT(low, 0.35);
  EXPECT_NEAR(world.terrain().height(world.data().q(0), world.data().q(1)), 0.3, 1e-12);
}

}  // namespace
}  // namespace podium::sim
