// The jumps' sparse reward terms (thesis eqs. 3.4, 3.12, 3.16) on hand-made inputs.
#include "jump_rewards.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "podium/base/error.h"

namespace podium::tasks::jump {
namespace {

TEST(JumpRewards, OmegaTermUsesTheEpisodeMeanRootSpeed) {
  EpisodeSums sums;
  sums.add(1.0, 0.0);
  sums.add(2.0, 0.0);
  sums.add(3.0, 0.0);
  EXPECT_DOUBLE_EQ(sums.mean_root_speed(), 2.0);
  EXPECT_DOUBLE_EQ(omega_reward(2.0), std::exp(-0.04));
  EXPECT_DOUBLE_EQ(jump_reward(true, false, sums, 48.0).omega, std::exp(-0.04));
  EXPECT_DOUBLE_EQ(omega_reward(0.0), 1.0);
}

TEST(JumpRewards, NaturalnessUsesTheEpisodeMeanL1OffsetAndCOffset) {
  EpisodeSums sums;
  sums.add(0.0, 10.0);
  sums.add(0.0, 30.0);                                                       // mean ‖a_offset‖₁ = 20
  EXPECT_DOUBLE_EQ(jump_reward(true, false, sums, 40.0).naturalness, 0.75);  // 1 − (20/40)²
  EXPECT_DOUBLE_EQ(jump_reward(true, false, sums, 20.0).naturalness, 0.0);   // at c_offset
  EXPECT_DOUBLE_EQ(jump_reward(true, false, sums, 10.0).naturalness, 0.0);   // clipped
  EXPECT_DOUBLE_EQ(jump_reward(true, false, EpisodeSums{}, 15.0).naturalness, 1.0);
}

TEST(JumpRewards, HeadFirstLandingScalesBySevenTenthsAndFailureGivesNothing) {
  EpisodeSums sums;
  sums.add(1.0, 12.0);
  const RewardTerms safe = jump_reward(true, false, sums, 48.0);
  const RewardTerms head = jump_reward(true, true, sums, 48.0);
  EXPECT_DOUBLE_EQ(head.safety, 0.7);
  EXPECT_DOUBLE_EQ(safe.safety, 1.0);
  EXPECT_DOUBLE_EQ(head.total(), 0.7 * safe.total());
  EXPECT_DOUBLE_EQ(safe.total(), std::exp(-0.02) * (1.0 - 0.0625));
  EXPECT_DOUBLE_EQ(jump_reward(false, false, sums, 48.0).total(), 0.0);
  EXPECT_DOUBLE_EQ(jump_reward(true, false, sums, 48.0, 0.25).total(), 0.25 * safe.total());
}

TEST(JumpRewards, NoveltyIsTheNearestKnownFeatureOverDThresholdClipped) {
  const std::vector<double> f = {0.0, 0.0, 0.0};
  const double pi = std::numbers::pi;
  EXPECT_DOUBLE_EQ(novelty_reward(f, {}), 1.0);
  EXPECT_DOUBLE_EQ(novelty_reward(f, {{pi / 4, 0.0, 0.0}}), 0.5);
  EXPECT_DOUBLE_EQ(novelty_reward(f, {{3.0, 0.0, 0.0}, {0.0, 0.3, 0.4}}), 0.5 / (pi / 2));  // nearest: ‖(0, .3, .4)‖ = .5
  EXPECT_DOUBLE_EQ(novelty_reward(f, {{0.0, 3.0, 0.0}}), 1.0);                              // beyond d_threshold
  EXPECT_DOUBLE_EQ(novelty_reward(f, {{0.0, 0.0, 0.0}}), 0.01);                             // the same strategy
  EXPECT_DOUBLE_EQ(novelty_reward(f, {{1.0, 0.0, 0.0}}, 2.0), 0.5);
  EXPECT_THROW(novelty_reward(f, {{1.0}}), base::UserError);
  EXPECT_THROW(novelty_reward(f, {{1.0, 0.0, 0.0}}, 0.0), base::UserError);
}

}  // namespace
}  // namespace podium::tasks::jump
