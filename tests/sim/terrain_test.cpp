// Terrain height queries agree with what Bullet collides against.
#include "podium/sim/terrain.h"

#include <gtest/gtest.h>

#include "podium/base/error.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/starts.h"
#include "podium/sim/world.h"

namespace podium::sim {
namespace {

TEST(Terrain, RoughTilesAreSeededAndWithinLevel) {
  const Terrain a(TerrainConfig::rough("hard", 7)), b(TerrainConfig::rough("hard", 7)), c(TerrainConfig::rough("hard", 8));
  double max_h = 0;
  bool differs = false;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      EXPECT_EQ(a.tile_height(0, i, j), b.tile_height(0, i, j));
      differs |= a.tile_height(0, i, j) != c.tile_height(0, i, j);
      max_h = std::max(max_h, a.tile_height(0, i, j));
    }
  EXPECT_TRUE(differs);
  EXPECT_LE(max_h, 0.2);
  EXPECT_GT(max_h, 0.1);
  EXPECT_THROW(TerrainConfig::rough("steep", 1), base::UserError);
}

TEST(Terrain, HeightMapSeesBoxesAndSlope) {
  TerrainConfig config;
  TerrainRegion slope;
  slope.kind = TerrainRegion::Kind::slope;
  slope.min = {0.0, -5.0};
  slope.max = {5.0, 5.0};
  slope.slope_rad = 0.1;
  config.regions.push_back(slope);
  config.boxes.push_back(
      BoxProp{"post", Eigen::Vector3d(2, 0, 0.5), Eigen::Vector3d(0.2, 0.2, 0.5), Eigen::Quaterniond::Identity(), 1.0, ""});
  const Terrain t(config);
  EXPECT_NEAR(t.height(1.0, 3.0), std::tan(0.1), 1e-12);
  EXPECT_NEAR(t.height(-1.0, 3.0), 0.0, 1e-12);  // outside the region: the plane
  EXPECT_NEAR(t.height(2.0, 0.0), 1.0, 1e-12);
  const auto map = t.height_map(1.5, 0.0, 0.0, 0.25, 0.0);  // row a = 4 is x + 0.5 = 2.0
  EXPECT_NEAR(map[4 * 5 + 2], 1.0, 1e-12);
  EXPECT_NEAR(map[0], std::tan(0.1) * 1.0, 1e-12);
  // The slope's box: its top face is the surface the height query reports.
  ASSERT_EQ(t.pieces().size(), 1u);
  const TerrainPiece& p = t.pieces()[0];
  const Eigen::Vector3d top_mid = p.center + p.rotation * Eigen::Vector3d(0, 0, p.half_extents.z());
  EXPECT_NEAR(top_mid.z(), t.height(top_mid.x(), top_mid.y()), 1e-12);
}

// Regions of every kind side by side, tiles of either sign, an inclined prop: the height query
// covers all of it, and bad configs are refused with the region or prop named.
TEST(Terrain, RegionsTilesOfEitherSignAndInclinedBoxes) {
  TerrainConfig config;
  TerrainRegion rough;
  rough.kind = TerrainRegion::Kind::rough;
  rough.min = {0.0, 0.0};
  rough.max = {4.0, 2.0};
  rough.tile_size_m = 0.5;
  rough.min_tile_height_m = -0.1;
  rough.max_tile_height_m = 0.1;
  rough.seed = 4;
  TerrainRegion flat;
  flat.min = {-3.0, 0.0};
  flat.max = {-1.0, 2.0};
  flat.height_m = 0.3;
  config.regions = {rough, flat};
  // A starting block: 30° about y, centred 1 m in front of the rough patch.
  config.boxes.push_back({"block", Eigen::Vector3d(0, -2, 0.1), Eigen::Vector3d(0.2, 0.3, 0.05),
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitY())), 1.0, ""});
  const Terrain t(config);
  EXPECT_EQ(t.pieces().size(), 8u * 4u + 1u);
  bool negative = false, positive = false;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j) {
      const double h = t.tile_height(0, i, j);
      negative |= h<0, positive |= h> 0;
      EXPECT_EQ(t.height(0.25 + 0.5 * i, 0.25 + 0.5 * j), h);
    }
  EXPECT_TRUE(negative && positive);
  EXPECT_EQ(t.height(-2.0, 1.0), 0.3);
  EXPECT_EQ(t.height(-0.5, 1.0), 0.0);
  EXPECT_EQ(t.region_at(-2.0, 1.0), 1);
  EXPECT_EQ(t.region_at(5.0, 1.0), -1);
  // The inclined block's top along its centre line: centre height + half thickness / cos 30°, tilted.
  EXPECT_NEAR(t.height(0.0, -2.0), 0.1 + 0.05 / std::cos(0.5236), 1e-9);
  EXPECT_NEAR(t.height(0.1, -2.0), 0.1 + 0.05 / std::cos(0.5236) - 0.1 * std::tan(0.5236), 1e-9);
  TerrainConfig overlapping = config;
  overlapping.regions[1].max.x() = 0.5;
  try {
    Terrain bad(overlapping);
    FAIL() << "overlapping regions accepted";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("terrain.regions[1]: overlaps terrain.regions[0]"), std::string::npos) << e.what();
  }
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
  config.terrain.boxes.push_back(BoxProp{"mat", Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(2.0, 2.0, 0.15),
                                         Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())), 1.0, "mat"});
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
