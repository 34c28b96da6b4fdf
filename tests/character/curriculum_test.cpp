// Curricula on scripted sequences, and their JSON state.
#include "podium/character/curriculum.h"

#include <gtest/gtest.h>

#include <cmath>

#include "podium/base/error.h"

namespace podium::character {
namespace {

// Weaker (get-up seed §5, App. D): β ← 0.95β exactly when the test return exceeds ω = 60.
TEST(Curriculum, StrengthAdvancesExactlyWhenTheTestReturnExceedsOmega) {
  ThresholdCurriculum weaker(ThresholdCurriculum::Config{});
  const double returns[] = {10, 59.9, 60.0, 60.1, 45, 80, 61};
  const bool advanced[] = {false, false, false, true, false, true, true};
  double beta = 1.0;
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(weaker.observe(returns[i]), advanced[i]) << "test " << i;
    if (advanced[i]) beta *= 0.95;
    EXPECT_DOUBLE_EQ(weaker.value(), beta);
  }
  EXPECT_EQ(weaker.level(), 3);
  EXPECT_NEAR(weaker.value(), 0.857375, 1e-12);  // three advances: β ≤ 0.857
}

// Thesis Table 3.1: scores accumulate; the bar rises by Δz when the sum passes R_T, up to 2 m.
TEST(Curriculum, BarRisesWhenTheAccumulatedRewardPassesItsThreshold) {
  ThresholdCurriculum bar({0.5, 1.0, 0.01, 30.0, true, 0.52});
  EXPECT_FALSE(bar.observe(12));
  EXPECT_FALSE(bar.observe(12));  // 24
  EXPECT_TRUE(bar.observe(12));   // 36 > 30: rise, restart the sum
  EXPECT_NEAR(bar.value(), 0.51, 1e-12);
  EXPECT_FALSE(bar.observe(29));
  EXPECT_TRUE(bar.observe(2));
  EXPECT_NEAR(bar.value(), 0.52, 1e-12);
  EXPECT_TRUE(bar.at_limit());
  EXPECT_FALSE(bar.observe(1000));
  EXPECT_NEAR(bar.value(), 0.52, 1e-12);
  EXPECT_THROW(ThresholdCurriculum({0.5, 1.0, 0.0, 30.0, true, 2.0}), base::UserError);    // never moves
  EXPECT_THROW(ThresholdCurriculum({0.5, 1.0, -0.01, 30.0, true, 2.0}), base::UserError);  // away from the limit
}

// Get-up seed §5: M_i = clip(1.5·N_{i−1}, 3e5, 8e5); the curriculum ends past M_i.
TEST(Curriculum, StepBudgetFollowsTheSeedsRule) {
  StepBudget budget(StepBudget::Config{});
  EXPECT_EQ(budget.budget(), 800000);  // level 0: N_max (the seed gives no M_0)
  budget.on_advance(100000);           // level 0 took 1e5 steps → M_1 = clip(1.5e5) = 3e5
  EXPECT_EQ(budget.budget(), 300000);
  EXPECT_FALSE(budget.exhausted(400000));
  EXPECT_TRUE(budget.exhausted(400001));
  budget.on_advance(350000);  // level 1 took 2.5e5 → M_2 = 3.75e5
  EXPECT_EQ(budget.budget(), 375000);
  budget.on_advance(950000);  // level 2 took 6e5 → M_3 = clip(9e5) = 8e5
  EXPECT_EQ(budget.budget(), 800000);
  StepBudget resumed(StepBudget::Config{});
  resumed.load_state(budget.state());
  EXPECT_EQ(resumed.budget(), 800000);
  EXPECT_EQ(resumed.exhausted(950000 + 800001), true);
  EXPECT_THROW(StepBudget::Config::from_json({{"min_steps", 9}, {"max_steps", 8}}, "curriculum.budget"), base::UserError);
}

// Curve get-up seed §4: 200 successes on the newest region unlock the next.
TEST(Curriculum, TerrainUnlocksAfterNSuccessesOnTheNewestLevel) {
  UnlockCurriculum terrain({{"flat", "easy", "medium", "hard"}, 3});
  EXPECT_FALSE(terrain.record(0, true));
  EXPECT_FALSE(terrain.record(0, false));
  EXPECT_FALSE(terrain.record(0, true));
  EXPECT_TRUE(terrain.record(0, true));
  EXPECT_EQ(terrain.unlocked(), 2);
  EXPECT_FALSE(terrain.record(0, true));  // an older level does not count
  base::Rng rng(1);
  int seen[2] = {0, 0};
  for (int i = 0; i < 100; ++i) ++seen[terrain.sample(rng)];
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  UnlockCurriculum resumed({{"flat", "easy", "medium", "hard"}, 3});
  resumed.load_state(terrain.state());
  EXPECT_EQ(resumed.unlocked(), 2);
  EXPECT_THROW(resumed.load_state({{"unlocked", 7}, {"successes", 0}}), base::UserError);
  EXPECT_EQ(resumed.level_name(1), "easy");
  // The seed's 200: the 200th success on the newest level unlocks, not the 199th.
  UnlockCurriculum seed({{"flat", "easy"}, 200});
  for (int k = 1; k < 200; ++k) ASSERT_FALSE(seed.record(0, true)) << k;
  EXPECT_EQ(seed.unlocked(), 1);
  EXPECT_TRUE(seed.record(0, true));
  EXPECT_EQ(seed.unlocked(), 2);
  // A fixed schedule opens the next level at once (§6.4's ablation), and no further than the last.
  UnlockCurriculum scheduled({{"flat", "easy", "medium"}, 200});
  EXPECT_TRUE(scheduled.open_next());
  EXPECT_TRUE(scheduled.open_next());
  EXPECT_FALSE(scheduled.open_next());
  EXPECT_EQ(scheduled.unlocked(), 3);
}

TEST(Curriculum, StateRoundTripsAndConfigErrorsNameThePath) {
  ThresholdCurriculum a(ThresholdCurriculum::Config::from_json({{"threshold", 5.0}}, "curriculum"));
  a.observe(6);
  a.observe(6);
  ThresholdCurriculum b(ThresholdCurriculum::Config::from_json({{"threshold", 5.0}}, "curriculum"));
  b.load_state(a.state());
  EXPECT_EQ(b.value(), a.value());
  EXPECT_EQ(b.level(), 2);
  try {
    ThresholdCurriculum::Config::from_json({{"factor", "fast"}}, "stages[0].task.curriculum");
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    EXPECT_EQ(std::string(e.what()), "stages[0].task.curriculum.factor: \"fast\" is not a number");
  }
}

// The configs are read by base::ConfigReader: ranges, unknown keys, errors naming the JSON path.
TEST(Curriculum, ConfigErrorsNameTheKeyAndTheRule) {
  const auto error_of = [](auto&& read) {
    try {
      read();
    } catch (const base::UserError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error_of([] {
              ThresholdCurriculum::Config::from_json({{"factr", 0.9}}, "c");
            }),
            "c.factr: unknown key (known: accumulate, factor, increment, initial, limit, threshold)");
  EXPECT_EQ(error_of([] { ThresholdCurriculum::Config::from_json({{"factor", 0}}, "c"); }), "c.factor: 0 is not > 0");
  EXPECT_EQ(error_of([] {
              StepBudget::Config::from_json({{"min_steps", 9}, {"max_steps", 8}}, "b");
            }),
            "b.min_steps: 9 is above max_steps 8");
  EXPECT_EQ(error_of([] { StepBudget::Config::from_json({{"max_steps", 1.5}}, "b"); }), "b.max_steps: 1.5 is not an integer");
  EXPECT_EQ(error_of([] {
              UnlockCurriculum::Config::from_json({{"levels", base::Json::array()}}, "u");
            }),
            "u.levels: [] needs at least one level");
  EXPECT_EQ(error_of([] {
              UnlockCurriculum::Config::from_json({{"levels", {"flat"}}, {"successes_to_unlock", 0}}, "u");
            }),
            "u.successes_to_unlock: 0 is not in [1, 2147483647]");
  const auto unlock = UnlockCurriculum::Config::from_json({{"levels", {"flat", "hard"}}}, "u");
  EXPECT_EQ(unlock.levels, (std::vector<std::string>{"flat", "hard"}));
  EXPECT_EQ(unlock.successes_to_unlock, 200);
}

}  // namespace
}  // namespace podium::character
