// The style-curve get-up's rewards (curve get-up seed eqs. 2–9), action filter (§3.4) and early
// termination (§5.3) on hand-made values.
#include "style_rewards.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "podium/character/frames.h"
#include "podium/sim/model.h"
#include "style_curve.h"

namespace podium::tasks::getup_curves {
namespace {

StyleCurve rising_curve() {
  StyleCurve c;
  c.name = "rise";
  c.duration_s = 3.0;
  for (int k = 0; k < kControlPoints; ++k) c.points.col(k) << 0.2 + 0.17 * k, 1.5, 0.2 + 0.17 * k;
  return c;
}

TEST(StyleRewards, HeightAndTorsoAreOneOnTheCurveAndFallOffItsKernels) {
  const StyleCurve curve = rising_curve();
  for (double t : {0.0, 0.4, 1.3, 2.9, 5.0}) {
    const StyleFeatures p = curve.target(t);
    EXPECT_EQ(height_reward(p(0), p(0)), 1.0);
    EXPECT_EQ(torso_reward(p(1), p(2), p(1), p(2)), 1.0);
  }
  EXPECT_NEAR(height_reward(1.0, 1.5), std::exp(-1.7 * 0.5), 1e-15);
  EXPECT_NEAR(height_reward(1.5, 1.0), std::exp(-1.7 * 0.5), 1e-15);
  EXPECT_NEAR(torso_reward(0.3, 2.0, 0.1, 2.5), std::exp(-1.5 * (0.2 + 0.5)), 1e-15);
}

TEST(StyleRewards, StandingPhaseIsNegligibleHalfwayAndOneAtTheTop) {
  EXPECT_LT(standing_phase(0.75, 1.5), 1e-4);  // φ = 0.5: e^−10
  EXPECT_GT(standing_phase(0.75, 1.5), 0.0);
  EXPECT_EQ(standing_phase(1.5, 1.5), 1.0);  // φ = 1
  EXPECT_EQ(standing_phase(1.7, 1.5), 1.0);  // a curve above its final height: φ clamped
  EXPECT_NEAR(standing_phase(1.35, 1.5), std::exp(-20 * 0.1), 1e-15);
}

TEST(StyleRewards, VelocityAndPoseTermsAreOneBeforeTheStandingPhase) {
  EXPECT_EQ(velocity_reward(0.0, 80.0), 1.0);
  EXPECT_EQ(pose_reward(0.0, 9.0), 1.0);
  EXPECT_NEAR(velocity_reward(1.0, 10.0), std::exp(-0.5), 1e-15);
  EXPECT_NEAR(pose_reward(1.0, 3.0), std::exp(-0.3), 1e-15);
  EXPECT_NEAR(velocity_reward(0.5, 10.0), 0.5 + 0.5 * std::exp(-0.5), 1e-15);
}

TEST(StyleRewards, NaturalnessIsZeroFromTheOffsetScaleOn) {
  StyleRewardInput in;
  in.final_target_h = 1.5;
  in.target << 0.4, 1.5, 0.3;
  in.achieved = in.target;
  for (double l1 : {10.0, 10.5, 40.0}) {
    in.offset_l1 = l1;
    const StyleRewardTerms r = style_rewards(in);
    EXPECT_EQ(r.natural, 0.0) << l1;
    EXPECT_EQ(r.total, 0.0) << l1;
  }
  in.offset_l1 = 5.0;
  const StyleRewardTerms r = style_rewards(in);
  EXPECT_DOUBLE_EQ(r.natural, 0.75);
  EXPECT_EQ(r.task, 1.0);  // on the curve, α ≈ 0
  EXPECT_DOUBLE_EQ(r.total, 0.75);
}

TEST(StyleRewards, TaskRewardIsTheProductOfItsTerms) {
  StyleRewardInput in;
  in.final_target_h = 1.5;
  in.target << 1.45, 1.5, 1.6;
  in.achieved << 1.3, 1.4, 1.7;
  in.angular_speed_norm = 6.0;
  in.rotation_distance_sum = 2.0;
  in.offset_l1 = 3.0;
  const StyleRewardTerms r = style_rewards(in);
  const double alpha = std::exp(-20 * (1 - 1.45 / 1.5));
  EXPECT_DOUBLE_EQ(r.alpha, alpha);
  EXPECT_DOUBLE_EQ(r.height, std::exp(-1.7 * 0.15));
  EXPECT_DOUBLE_EQ(r.torso, std::exp(-1.5 * 0.2));
  EXPECT_DOUBLE_EQ(r.velocity, 1 - alpha + alpha * std::exp(-0.3));
  EXPECT_DOUBLE_EQ(r.pose, 1 - alpha + alpha * std::exp(-0.2));
  EXPECT_DOUBLE_EQ(r.task, r.height * r.torso * r.velocity * r.pose);
  EXPECT_DOUBLE_EQ(r.natural, 1 - 0.09);
  EXPECT_DOUBLE_EQ(r.total, r.task * r.natural);
}

TEST(StyleRewards, JointRotationDistanceSumsTheJointsRelativeAngles) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const Eigen::VectorXd neutral = model->standing_pose();
  EXPECT_EQ(joint_rotation_distance(*model, neutral, neutral), 0.0);
  Eigen::VectorXd q = neutral;
  const sim::Link& chest = model->link("chest");
  character::set_quat(q, chest.q_index, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0.5).normalized())));
  q(model->link("right_knee").q_index) -= 0.2;
  q.segment<7>(0) << 4, 5, 0.3, 0, 1, 0, 0;  // the root's place and rotation do not count
  EXPECT_NEAR(joint_rotation_distance(*model, q, neutral), 0.5, 1e-12);
  q.segment<4>(chest.q_index) *= -1.0;  // the same rotation
  EXPECT_NEAR(joint_rotation_distance(*model, q, neutral), 0.5, 1e-12);
}

TEST(CurveActionFilter, StepResponseIsOneMinusPointEightToTheN) {
  ActionFilter filter(3);
  const Eigen::VectorXd step = Eigen::VectorXd::Ones(3);
  for (int n = 1; n <= 30; ++n) {
    const Eigen::VectorXd& y = filter.step(step);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(y(k), 1.0 - std::pow(0.8, n), 1e-12) << n;
  }
  filter.reset();
  EXPECT_EQ(filter.value(), Eigen::VectorXd::Zero(3));
  EXPECT_NEAR(filter.step(2.0 * step)(1), 0.4, 1e-15);
  EXPECT_THROW(ActionFilter(3, 0.0), base::UserError);
}

TEST(CurveEarlyTermination, EndsAfterTenLowStepsAtThirtyHertzNotNine) {
  EarlyTermination end(1.0 / 30.0);
  for (int n = 1; n <= 9; ++n) EXPECT_FALSE(end.step(0.05, false)) << n;
  EXPECT_TRUE(end.step(0.05, false));
  end.reset();
  for (int n = 1; n <= 9; ++n) EXPECT_FALSE(end.step(0.0, false)) << n;
  EXPECT_FALSE(end.step(0.1, false));  // not below the floor: the run restarts
  for (int n = 1; n <= 9; ++n) EXPECT_FALSE(end.step(0.09, false)) << n;
  EXPECT_TRUE(end.step(0.09, false));
}

TEST(CurveEarlyTermination, CountsTheHeadOnTheGroundOnItsOwn) {
  EarlyTermination end(1.0 / 30.0);
  for (int n = 1; n <= 9; ++n) EXPECT_FALSE(end.step(0.9, true)) << n;
  EXPECT_EQ(end.head_down_steps(), 9);
  EXPECT_TRUE(end.step(0.9, true));
  end.reset();
  // Alternating conditions sustain neither.
  for (int n = 1; n <= 40; ++n) EXPECT_FALSE(end.step(n % 2 ? 0.0 : 0.9, n % 2 == 0)) << n;
  // At 60 Hz more than 300 ms is 19 steps.
  EarlyTermination fast(1.0 / 60.0);
  for (int n = 1; n <= 18; ++n) EXPECT_FALSE(fast.step(0.0, false)) << n;
  EXPECT_TRUE(fast.step(0.0, false));
}

}  // namespace
}  // namespace podium::tasks::getup_curves
