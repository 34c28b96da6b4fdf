// The get-up rewards of seed 001's appendix B on hand-made states, each term at known values.
#include "getup_rewards.h"

#include <gtest/gtest.h>

#include <cmath>

#include "podium/sim/model.h"

namespace podium::tasks::getup {
namespace {

TEST(GetupRewards, HeadHeightIsOneAboveTheBoundAndTheMarginValueBelowIt) {  // eq. 5
  EXPECT_EQ(r_head(1.55), 1.0);
  EXPECT_EQ(r_head(2.0), 1.0);
  EXPECT_NEAR(r_head(1.55 - 0.37), 0.1, 1e-12);
  EXPECT_LT(r_head(1.0), 0.1);
  EXPECT_GT(r_head(1.4), r_head(1.3));
  // Long-tailed: a lying head still earns a little, more the higher it is.
  EXPECT_NEAR(r_head(0.25), 1.0 / (std::pow(1.3 / 0.37 * 3.0, 2) + 1.0), 1e-12);
  EXPECT_GT(r_head(0.6), r_head(0.25));
}

TEST(GetupRewards, StraightTorsoCountsOnlyAboveHalfAMetre) {  // eq. 6
  EXPECT_EQ(r_straight(-1.0, 0.3), 1.0);                      // lying: not applied
  EXPECT_EQ(r_straight(0.95, 0.9), 1.0);
  EXPECT_NEAR(r_straight(0.9 - 0.95, 0.9), 0.5, 1e-12);  // linear: half way down the margin
  EXPECT_EQ(r_straight(0.9 - 1.9, 0.9), 0.0);            // value 0 at the margin
}

TEST(GetupRewards, ComVelocityAveragesItsTwoComponents) {  // eq. 7 and App. B.3
  EXPECT_EQ(r_vcom({0.3, -0.3}), 1.0);
  EXPECT_NEAR(r_vcom({0.3 + 1.2, 0.0}), 0.55, 1e-12);
  EXPECT_NEAR(r_vcom({1.5, -1.5}), 0.1, 1e-12);
  EXPECT_EQ(r_vcom({0.0, 0.0}, 0.0), 1.0);
  EXPECT_NEAR(r_vcom({1.2, 1.2}, 0.0), 0.1, 1e-12);  // standing: bounds [0, 0]
  EXPECT_LT(r_vcom({0.1, 0.0}, 0.0), 1.0);
}

TEST(GetupRewards, FeetFartherThanTheBoundLoseTheReward) {  // eq. 8
  EXPECT_EQ(r_feet(0.0), 1.0);
  EXPECT_EQ(r_feet(0.9), 1.0);
  EXPECT_NEAR(r_feet(0.9 + 0.19), 0.75, 1e-12);  // quadratic: 1 − (half the margin)²
  EXPECT_EQ(r_feet(0.9 + 0.38), 0.0);
}

TEST(GetupRewards, WeakRewardIsTheProductOfItsTerms) {  // eq. 2
  WeakState s;
  s.head_height_m = 1.3;
  s.com_height_m = 0.8;
  s.com_velocity_xy = {0.5, -0.1};
  s.torso_up_z = 0.7;
  s.feet_distance_m = 1.0;
  const double expected = r_head(1.3) * r_straight(0.7, 0.8) * r_vcom({0.5, -0.1}) * r_feet(1.0);
  EXPECT_DOUBLE_EQ(reward_weak(s), expected);
  EXPECT_GT(expected, 0.0);
  EXPECT_LT(expected, r_head(1.3));
  WeakState standing;
  standing.head_height_m = 1.56, standing.com_height_m = 0.9, standing.torso_up_z = 1.0, standing.feet_distance_m = 0.2;
  EXPECT_EQ(reward_weak(standing), 1.0);
}

TEST(GetupRewards, SlowRewardTracksComOrientationAndHips) {  // eqs. 3, 9–11
  EXPECT_EQ(reward_slow(SlowState{}), 1.0);
  EXPECT_NEAR(r_com(0.5), 0.1, 1e-12);
  EXPECT_NEAR(r_com(-0.5), 0.1, 1e-12);
  EXPECT_NEAR(r_ori({0.03 + 0.6, 0.0, -0.03}), 0.3, 1e-12);
  EXPECT_NEAR(r_ori({0.63, 0.63, 0.0}), 0.09, 1e-12);
  EXPECT_NEAR(r_hip({1.8, 0.0}), 0.55, 1e-12);
  SlowState s;
  s.com_height_error_m = 0.5;
  s.hip_velocity_error = {1.8, -1.8};  // r_hip = 0.1
  EXPECT_NEAR(reward_slow(s), 0.1 * 1.0 * (0.1 + 2.0) / 3.0, 1e-12);
}

TEST(GetupRewards, BalanceRewardAddsThePoseKernel) {  // eqs. 4 and 12
  EXPECT_EQ(reward_balance(BalanceState{.torso_up_z = 1.0, .com_height_m = 0.9}), 1.0);
  EXPECT_NEAR(r_pose(4.0), std::exp(-1.0), 1e-15);
  BalanceState s{.com_velocity_xy = {1.2, 1.2},
                 .torso_up_z = 0.9 - 0.95,
                 .com_height_m = 0.8,
                 .com_height_error_m = 0.5,
                 .pose_squared_error = 4.0};
  EXPECT_NEAR(reward_balance(s), 0.1 * 0.5 * 0.1 * std::exp(-1.0), 1e-12);
}

TEST(GetupRewards, TheHeadTopOfHumanoid21ReachesTheSeedsBoundStanding) {
  const auto model = sim::load_shipped_model("humanoid21");
  const BodyReadings readings = BodyReadings::of(*model);
  EXPECT_DOUBLE_EQ(readings.head_top_m, 0.09);
  // Standing head origin: root 1.282 m + 0.19 m; its top 1.562 m is above eq. 5's 1.55 m.
  EXPECT_EQ(r_head(1.282 + 0.19 + readings.head_top_m), 1.0);
  EXPECT_LT(r_head(1.282 + 0.19), 1.0);
}

}  // namespace
}  // namespace podium::tasks::getup
