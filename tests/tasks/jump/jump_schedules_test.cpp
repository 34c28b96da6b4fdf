// The jumps' schedules (thesis §3.6.1, Table 3.1): ρ, f_control and c_offset at ρ = 0, 0.5, 1 and
// clipped; the accumulated-reward curriculum advances when the accumulator exceeds R_T, not before.
#include "jump_schedules.h"

#include <gtest/gtest.h>

#include "podium/base/error.h"

namespace podium::tasks::jump {
namespace {

TEST(JumpSchedules, RatioIsTwoZMinusOneForTheBarAndZForTheBox) {
  EXPECT_DOUBLE_EQ(difficulty_ratio(JumpKind::high_jump, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(difficulty_ratio(JumpKind::high_jump, 0.75), 0.5);
  EXPECT_DOUBLE_EQ(difficulty_ratio(JumpKind::high_jump, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(difficulty_ratio(JumpKind::obstacle, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(difficulty_ratio(JumpKind::obstacle, 2.5), 2.5);
}

TEST(JumpSchedules, ControlRateAtRhoZeroHalfOneAndClipped) {
  EXPECT_EQ(control_hz_for(0.0, 600.0), 10.0);
  EXPECT_EQ(control_hz_for(0.5, 600.0), 20.0);
  EXPECT_EQ(control_hz_for(1.0, 600.0), 30.0);
  EXPECT_EQ(control_hz_for(-3.0, 600.0), 10.0);
  EXPECT_EQ(control_hz_for(7.0, 600.0), 30.0);
  // Rounded to a whole-Hz divisor of the simulation rate: 10 + 20·0.37 = 17.4 → 15 (not 20).
  EXPECT_EQ(control_hz_for(0.37, 600.0), 15.0);
  EXPECT_EQ(control_hz_for(0.05, 600.0), 10.0);  // 11: a tie of 10 and 12 goes to the lower rate
  EXPECT_EQ(control_hz_for(0.5, 500.0), 20.0);
  EXPECT_EQ(control_hz_for(0.3, 500.0), 20.0);  // 16 → 20 (500's divisors: 10, 20, 25)
  for (double rho = 0.0; rho <= 1.0; rho += 0.01) {
    const double f = control_hz_for(rho, 600.0);
    EXPECT_EQ(std::fmod(600.0, f), 0.0) << "ρ " << rho;
  }
  EXPECT_THROW(control_hz_for(0.5, 600.5), base::UserError);
  EXPECT_THROW(control_hz_for(0.5, 20.0), base::UserError);
}

TEST(JumpSchedules, OffsetCoefficientAtRhoZeroHalfOneAndClipped) {
  EXPECT_DOUBLE_EQ(offset_coefficient(0.0), 48.0);
  EXPECT_DOUBLE_EQ(offset_coefficient(0.5), 31.5);
  EXPECT_DOUBLE_EQ(offset_coefficient(1.0), 15.0);
  EXPECT_DOUBLE_EQ(offset_coefficient(-1.0), 48.0);
  EXPECT_DOUBLE_EQ(offset_coefficient(4.0), 15.0);
}

TEST(JumpCurriculum, HighJumpBarRisesWhenTheAccumulatorExceedsRTAndNotBefore) {
  character::ThresholdCurriculum bar(difficulty_curriculum(JumpKind::high_jump));
  EXPECT_DOUBLE_EQ(bar.value(), 0.50);
  EXPECT_FALSE(bar.observe(10.0));
  EXPECT_FALSE(bar.observe(10.0));
  EXPECT_FALSE(bar.observe(10.0));  // accumulated exactly R_T = 30: not past it
  EXPECT_DOUBLE_EQ(bar.value(), 0.50);
  EXPECT_TRUE(bar.observe(0.01));  // 30.01 > 30
  EXPECT_NEAR(bar.value(), 0.51, 1e-12);
  EXPECT_FALSE(bar.observe(29.99));  // the accumulator restarted at 0
  EXPECT_TRUE(bar.observe(0.02));
  EXPECT_NEAR(bar.value(), 0.52, 1e-12);
  EXPECT_EQ(bar.level(), 2);
  for (int i = 0; i < 1000; ++i) bar.observe(31.0);  // one level per iteration, up to z_max
  EXPECT_DOUBLE_EQ(bar.value(), 2.00);
  EXPECT_TRUE(bar.at_limit());
}

TEST(JumpCurriculum, ObstacleWidthFollowsTable31) {
  character::ThresholdCurriculum width(difficulty_curriculum(JumpKind::obstacle));
  EXPECT_DOUBLE_EQ(width.value(), 0.05);
  EXPECT_FALSE(width.observe(49.0));
  EXPECT_FALSE(width.observe(1.0));  // 50: not past R_T
  EXPECT_TRUE(width.observe(0.5));
  EXPECT_NEAR(width.value(), 0.10, 1e-12);
  for (int i = 0; i < 100; ++i) width.observe(51.0);
  EXPECT_DOUBLE_EQ(width.value(), 2.50);
}

TEST(JumpSchedules, KindNamesRoundTripAndUnknownNamesAreRejected) {
  EXPECT_EQ(parse_jump_kind(jump_kind_name(JumpKind::high_jump), "kind"), JumpKind::high_jump);
  EXPECT_EQ(parse_jump_kind(jump_kind_name(JumpKind::obstacle), "kind"), JumpKind::obstacle);
  try {
    parse_jump_kind("long_jump", "config.kind");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_STREQ(e.what(), "config.kind: \"long_jump\" is not one of high_jump, obstacle");
  }
}

}  // namespace
}  // namespace podium::tasks::jump
