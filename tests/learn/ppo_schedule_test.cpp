// PPO's learning-rate and σ schedules: linear, or stepped in equal intervals (curve get-up seed
// §5.6: 1e-4 → 2e-5 and σ 0.6 → 0.3, a step every 20M of 100M simulation steps).
#include <gtest/gtest.h>

#include <string>

#include "podium/base/error.h"
#include "podium/learn/ppo.h"

namespace podium::learn {
namespace {

TEST(PpoSchedule, LinearMovesInProportionAndHoldsTheEnd) {
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 0, 100), 0.6);
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 50, 100), 0.45);
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 100, 100), 0.3);
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 250, 100), 0.3);
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 7, 0), 0.3);  // no span: the end at once
}

TEST(PpoSchedule, SteppedHoldsEachLevelForItsIntervalAndEndsAtTheEnd) {
  // The seed's learning rate over its 100M steps: 5 levels, 20M each.
  const double start = 1e-4, end = 2e-5;
  const std::int64_t span = 100'000'000, interval = 20'000'000;
  for (int k = 0; k < 5; ++k) {
    const double level = start + (end - start) * k / 4.0;
    EXPECT_DOUBLE_EQ(annealed(start, end, k * interval, span, 5), level) << k;
    EXPECT_DOUBLE_EQ(annealed(start, end, (k + 1) * interval - 1, span, 5), level) << k;
  }
  EXPECT_DOUBLE_EQ(annealed(start, end, span, span, 5), end);
  EXPECT_DOUBLE_EQ(annealed(start, end, 3 * span, span, 5), end);
  // Two levels: the start for the first half, the end from the middle on.
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 49, 100, 2), 0.6);
  EXPECT_DOUBLE_EQ(annealed(0.6, 0.3, 50, 100, 2), 0.3);
}

TEST(PpoSchedule, ConfigReadsTheLevelsAndRefusesOne) {
  EXPECT_EQ(PpoConfig::from_json({{"schedule_levels", 5}}).schedule_levels, 5);
  EXPECT_EQ(PpoConfig().schedule_levels, 0);  // linear unless asked
  PpoConfig one;
  one.schedule_levels = 1;
  try {
    Ppo ppo(one, {{0.0}, {1.0}}, {{-1.0}, {1.0}}, 0);
    FAIL() << "schedule_levels 1 accepted";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("schedule_levels 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace podium::learn
