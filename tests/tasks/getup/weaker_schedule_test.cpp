// Algorithm 1's curriculum decisions on a scripted sequence of test returns (advances exactly when
// the return exceeds ω; ends when a level needs more than M_i steps, and then holds the last
// strength passed), and the export rule's ranking where the curriculum does not decide.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "discover_weaker.h"
#include "podium/base/rng.h"

namespace podium::tasks::getup {
namespace {

using Decision = WeakerSchedule::Decision;

TEST(WeakerSchedule, AdvancesAboveOmegaAndEndsAfterItsStepBudget) {
  WeakerSchedule s({}, {});  // App. D: β 0.95, ω 60, N_min 3e5, N_max 8e5; §5's factor 1.5
  EXPECT_EQ(s.strength(), 1.0);
  EXPECT_EQ(s.on_test(20'000, 10.0), Decision::carry_on);
  EXPECT_EQ(s.on_test(40'000, 60.0), Decision::carry_on);  // not above ω
  EXPECT_EQ(s.on_test(60'000, 60.5), Decision::advance);
  EXPECT_DOUBLE_EQ(s.strength(), 0.95);
  EXPECT_EQ(s.on_test(80'000, 61.0), Decision::advance);
  EXPECT_DOUBLE_EQ(s.strength(), 0.95 * 0.95);
  // N_1 = 20 000: M_2 = clip(1.5 · 20 000, 3e5, 8e5) = 3e5 steps after 80 000.
  EXPECT_EQ(s.on_test(380'000, 59.0), Decision::carry_on);  // used exactly M_2
  EXPECT_FALSE(s.ended());
  EXPECT_EQ(s.on_test(400'000, 59.0), Decision::end_curriculum);  // more than M_2
  EXPECT_TRUE(s.ended());
  EXPECT_DOUBLE_EQ(s.strength(), 0.95);  // back to the last strength passed
  EXPECT_EQ(s.level(), 2);
  // Training goes on there; no test advances the ended curriculum.
  EXPECT_EQ(s.on_test(420'000, 90.0), Decision::carry_on);
  EXPECT_DOUBLE_EQ(s.strength(), 0.95);
  EXPECT_EQ(s.level(), 2);
}

TEST(WeakerSchedule, TheBudgetGrowsWithTheLastLevelsSteps) {
  WeakerSchedule s({}, {});
  EXPECT_EQ(s.on_test(5'000'000, 0.0), Decision::carry_on);  // Discover has no budget
  EXPECT_EQ(s.on_test(5'020'000, 61.0), Decision::advance);  // N_0 = 5.02e6: M_1 = N_max
  EXPECT_EQ(s.on_test(5'820'000, 0.0), Decision::carry_on);
  EXPECT_EQ(s.on_test(5'840'000, 0.0), Decision::end_curriculum);
  EXPECT_DOUBLE_EQ(s.strength(), 1.0);
  WeakerSchedule t({}, {});
  EXPECT_EQ(t.on_test(400'000, 61.0), Decision::advance);  // N_0 = 4e5: M_1 = 6e5
  EXPECT_EQ(t.on_test(1'000'000, 0.0), Decision::carry_on);
  EXPECT_EQ(t.on_test(1'020'000, 0.0), Decision::end_curriculum);
}

TEST(WeakerSchedule, ItsStateRoundTrips) {
  WeakerSchedule s({}, {});
  s.on_test(100'000, 70.0);
  s.on_test(200'000, 70.0);
  WeakerSchedule t({}, {});
  t.load_state(s.state());
  EXPECT_DOUBLE_EQ(t.strength(), 0.95 * 0.95);
  EXPECT_EQ(t.on_test(200'000 + 300'001, 0.0), s.on_test(200'000 + 300'001, 0.0));
  // An ended curriculum stays ended, at the last strength passed.
  WeakerSchedule u({}, {});
  u.load_state(s.state());
  EXPECT_TRUE(u.ended());
  EXPECT_DOUBLE_EQ(u.strength(), 0.95);
  EXPECT_EQ(u.on_test(600'000, 99.0), Decision::carry_on);
}

// Where the curriculum does not choose the export: a policy that stood at more starts wins over
// a higher return (a leap loop earns more on the way); at equal stands the return decides.
TEST(WeakerExport, StandsRankAboveReturn) {
  const character::Figures leap = {{"stood_rate", 0.0}, {"test_return", 95.0}};
  const character::Figures stand = {{"stood_rate", 0.1}, {"test_return", 40.0}};
  EXPECT_TRUE(exports_over(stand, leap));
  EXPECT_FALSE(exports_over(leap, stand));
  const character::Figures better_stand = {{"stood_rate", 0.1}, {"test_return", 41.0}};
  EXPECT_TRUE(exports_over(better_stand, stand));
  EXPECT_FALSE(exports_over(stand, better_stand));
  EXPECT_FALSE(exports_over(stand, stand));                                      // a tie keeps what was exported
  EXPECT_THROW(exports_over(stand, {{"test_return", 73.7}}), std::logic_error);  // a test must report its stands
}

// A schedule state without its end (an older layout) is refused, naming the state.
TEST(WeakerSchedule, AStateWithoutItsEndIsRefused) {
  WeakerSchedule s({}, {});
  base::Json old = s.state();
  old.erase("ended");
  WeakerSchedule t({}, {});
  EXPECT_THROW(t.load_state(old), base::UserError);
}

// After the curriculum ends, each training episode's strength is clip(N(β, ε), β, 1) with β the last
// strength passed (the seed repository's main.py update_power and env.py sample_power): 10,000
// draws of a training GetupEnv never fall below it; during the curriculum they may (floor 0.4).
TEST(WeakerSchedule, AfterTheCurriculumTheSampledStrengthNeverFallsBelowTheLastPassed) {
  WeakerSchedule s({}, {});
  EXPECT_EQ(s.on_test(20'000, 61.0), Decision::advance);
  EXPECT_EQ(s.on_test(40'000, 61.0), Decision::advance);
  EnvSettings env;
  env.fall.control_steps = 1;
  EXPECT_EQ(strength_floor(s, env.min_strength), 0.4);
  EXPECT_EQ(s.on_test(40'000 + 300'020, 0.0), Decision::end_curriculum);
  const double beta = s.strength(), floor = strength_floor(s, env.min_strength);
  EXPECT_DOUBLE_EQ(beta, 0.95);
  EXPECT_EQ(floor, beta);
  GetupEnv trained(env, std::make_shared<double>(beta), true, std::make_shared<double>(floor));
  base::Rng rng(3);
  double lowest = 1.0, sum = 0.0;
  int at_floor = 0;
  for (int k = 0; k < 10'000; ++k) {
    trained.begin_episode(rng);
    lowest = std::min(lowest, trained.strength());
    sum += trained.strength();
    at_floor += trained.strength() == beta;
  }
  EXPECT_GE(lowest, beta);
  EXPECT_GT(at_floor, 4'000);  // about half the draws fall below β and are clipped to it
  EXPECT_LT(at_floor, 6'000);
  EXPECT_GT(sum / 10'000, beta);
  // The same draws with the curriculum's floor do go below β.
  GetupEnv during(env, std::make_shared<double>(beta), true);
  base::Rng again(3);
  double lowest_during = 1.0;
  for (int k = 0; k < 10'000; ++k) {
    during.begin_episode(again);
    lowest_during = std::min(lowest_during, during.strength());
  }
  EXPECT_LT(lowest_during, beta - 0.1);
}

}  // namespace
}  // namespace podium::tasks::getup
