// The captured techniques as Stage 1 features: they must be told apart by the stored strategy
// definition (the feature must separate real techniques), and a feature is labelled by the nearest one.
#include "captured_techniques.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "jump_test_util.h"
#include "podium/base/error.h"
#include "strategy_feature.h"

namespace podium::tasks::jump {
namespace {

TEST(CapturedTechniques, FlopStraddleAndScissorArePairwiseDistinctStrategies) {
  const auto dir = testing::captured_jump_dir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/jump absent (PODIUM_SHARED_DIR)";
  const auto techniques = captured_techniques(dir / "motions/beyond", sim::load_shipped_model("athlete"));
  ASSERT_EQ(techniques.size(), 3u);
  for (const auto& t : techniques)
    std::printf("%s (%s): up-angle %.3f rad at the COM peak %.3f m\n", t.name.c_str(), t.file.c_str(), t.up_angle_rad,
                t.peak_com_m);
  for (std::size_t i = 0; i < techniques.size(); ++i)
    for (std::size_t j = i + 1; j < techniques.size(); ++j)
      EXPECT_GT(std::abs(techniques[i].up_angle_rad - techniques[j].up_angle_rad), kUpAngleStrategyThresholdRad)
          << techniques[i].name << " and " << techniques[j].name << " would be one strategy";
  // Each labels itself.
  for (const auto& t : techniques) EXPECT_EQ(nearest_technique(techniques, t.up_angle_rad).name, t.name);
}

TEST(CapturedTechniques, NearestIsByUpAngleAndAMissingFolderIsNamed) {
  const std::vector<CapturedTechnique> techniques = {
      {"Fosbury flop", "a", 0.3, 1.0}, {"scissor", "b", 1.6, 1.0}, {"straddle", "c", 2.9, 1.0}};
  EXPECT_EQ(nearest_technique(techniques, 0.0).name, "Fosbury flop");
  EXPECT_EQ(nearest_technique(techniques, 1.2).name, "scissor");
  EXPECT_EQ(nearest_technique(techniques, 2.4).name, "straddle");
  try {
    captured_techniques("/no/such/folder", sim::load_shipped_model("athlete"));
    ADD_FAILURE() << "expected a UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/folder/VC5_high_jump__fosbury_flop_06.txt: no such file"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace podium::tasks::jump
