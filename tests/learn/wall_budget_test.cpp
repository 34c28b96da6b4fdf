// The wall-clock limit of a training loop: which rounds it lets run, and its state across a resume.
#include "podium/learn/wall_budget.h"

#include <gtest/gtest.h>

#include <chrono>

#include "podium/base/error.h"

namespace podium::learn {
namespace {

TEST(WallBudget, WithoutALimitEveryRoundFits) {
  WallBudget clock(0.0);
  EXPECT_FALSE(clock.limited());
  for (int i = 0; i < 5; ++i) clock.add_round(1e6);
  EXPECT_TRUE(clock.another_round_fits());
  EXPECT_EQ(clock.fraction_used(), 0.0);
}

TEST(WallBudget, ARoundRunsOnlyIfItEndsInsideTheLimitAtTheLastRoundsLength) {
  WallBudget clock(1.0);                    // 60 s
  EXPECT_TRUE(clock.another_round_fits());  // the first round always runs
  int rounds = 0;
  while (clock.another_round_fits()) clock.add_round(11.0), ++rounds;
  EXPECT_EQ(rounds, 5);  // 55 s spent: a sixth 11 s round would end at 66 s
  EXPECT_DOUBLE_EQ(clock.spent_s(), 55.0);
  EXPECT_NEAR(clock.fraction_used(), 55.0 / 60.0, 1e-12);

  WallBudget exact(1.0);
  for (int i = 0; i < 5; ++i) exact.add_round(12.0);
  EXPECT_FALSE(exact.another_round_fits());  // 60 s spent: nothing fits
  WallBudget edge(1.0);
  for (int i = 0; i < 4; ++i) edge.add_round(12.0);
  EXPECT_TRUE(edge.another_round_fits());  // 48 + 12 = 60: ends exactly at the limit
}

TEST(WallBudget, AResumedClockGoesOnFromItsState) {
  WallBudget first(1.0);
  first.add_round(20.0);
  first.add_round(30.0);
  const WallBudget resumed(1.0, first.state());
  EXPECT_DOUBLE_EQ(resumed.spent_s(), 50.0);
  EXPECT_FALSE(resumed.another_round_fits());  // 50 + the last 30 s is past 60
  const WallBudget fresh(1.0, nullptr);
  EXPECT_EQ(fresh.spent_s(), 0.0);
  EXPECT_THROW(WallBudget(1.0, base::Json{{"spent_s", 1.0}}), base::UserError);
}

TEST(WallBudget, ATimedRoundCountsTheTimeBetweenItsStartAndEnd) {
  WallBudget clock(1.0);
  clock.start_round();
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(5);
  while (std::chrono::steady_clock::now() < until) {
  }
  clock.end_round();
  EXPECT_GE(clock.spent_s(), 0.005);
  EXPECT_LT(clock.spent_s(), 60.0);  // a round is counted once, in seconds
  EXPECT_EQ(clock.state().at("last_round_s").get<double>(), clock.spent_s());
}

TEST(WallBudget, SaysWhatEndedTheLoop) {
  EXPECT_EQ(WallBudget::stopped_by(400, 400), "steps");
  EXPECT_EQ(WallBudget::stopped_by(100, 400), "time");
  WallBudget clock(2.0);
  clock.add_round(90.0);
  EXPECT_EQ(clock.end_message("getup", 100, 400), "getup: training ended by time at environment step 100 after 1.5 min");
}

}  // namespace
}  // namespace podium::learn
