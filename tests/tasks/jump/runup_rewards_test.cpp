// The run-up's task reward (thesis §3.6.1 eqs. 3.13, 3.14) on hand-made end states, and the
// hand-over rule from the run-up policy to the jump policy on a scripted sequence of steps.
#include "runup_rewards.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "takeoff.h"

namespace podium::tasks::jump {
namespace {

const std::vector<double> kHighJump = {1.0, -1.5, 0.5, 1.2};  // α, ω_x, ω_y, v_y
const std::vector<double> kObstacle = {0.5, -2.0, 1.0};       // ω_x, ω_y, ω_z

TEST(RunupReward, TargetsAreTheStrategysTakeoffFeatures) {
  const RunupTarget high = runup_target(JumpKind::high_jump, kHighJump);
  EXPECT_EQ(high.root_omega, Eigen::Vector3d(-1.5, 0.5, kHighJumpTurnRate));  // ω_z fixed (§3.6.1)
  EXPECT_DOUBLE_EQ(high.lateral_speed, 1.2);
  const RunupTarget box = runup_target(JumpKind::obstacle, kObstacle);
  EXPECT_EQ(box.root_omega, Eigen::Vector3d(0.5, -2.0, 1.0));
  EXPECT_THROW(runup_target(JumpKind::obstacle, kHighJump), base::UserError);
}

TEST(RunupReward, HighJumpIsOneAtTheTargetAndFallsAsEq313) {
  const RunupTarget t = runup_target(JumpKind::high_jump, kHighJump);
  RootMotion end{t.root_omega, Eigen::Vector3d(6.0, t.lateral_speed, 0.2)};
  EXPECT_DOUBLE_EQ(runup_task_reward(t, end), 1.0);
  EXPECT_DOUBLE_EQ(runup_task_reward(t, {t.root_omega, Eigen::Vector3d(3.0, t.lateral_speed, -1.0)}), 1.0);  // v_x, v_z: free
  for (int axis = 0; axis < 3; ++axis)
    for (double d : {0.1, 0.5, 2.0}) {
      RootMotion off = end;
      off.omega(axis) += (axis == 1 ? -d : d);  // ‖·‖₁: either sign
      EXPECT_NEAR(runup_task_reward(t, off), std::exp(-d / 3.0), 1e-12) << axis << " " << d;
    }
  for (double d : {0.1, 0.3, 1.0}) {
    RootMotion off = end;
    off.velocity.y() -= d;
    EXPECT_NEAR(runup_task_reward(t, off), std::exp(-0.7 * d * d), 1e-12) << d;
    off.omega += Eigen::Vector3d(0.2, -0.1, 0.3);  // the two errors add in the exponent
    EXPECT_NEAR(runup_task_reward(t, off), std::exp(-0.6 / 3.0 - 0.7 * d * d), 1e-12) << d;
  }
}

TEST(RunupReward, ObstacleIsOneAtTheTargetAndFallsAsEq314) {
  const RunupTarget t = runup_target(JumpKind::obstacle, kObstacle);
  const RootMotion end{t.root_omega, Eigen::Vector3d(5.0, 0.0, 0.0)};
  EXPECT_DOUBLE_EQ(runup_task_reward(t, end), 1.0);
  RootMotion lateral = end;
  lateral.velocity.y() = 2.0;  // no speed term in eq. 3.14
  EXPECT_DOUBLE_EQ(runup_task_reward(t, lateral), 1.0);
  RootMotion off = end;
  off.omega += Eigen::Vector3d(0.3, -0.6, 0.9);
  EXPECT_NEAR(runup_task_reward(t, off), std::exp(-1.8 / 3.0), 1e-12);
}

TEST(RunupReward, RootMotionIsInTheHeadingFrame) {
  // A root turned by 1 rad about the vertical, moving forward along its own x and turning left:
  // in the heading frame, forward is x and the turn is about z, wherever it faces.
  Eigen::VectorXd q = Eigen::VectorXd::Zero(7);
  character::set_quat(q, 3, Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ())));
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(6);
  qd << 0.2, -0.4, 3.0, 6.0, 0.5, 0.0;  // root frame
  const RootMotion m = root_motion(q, qd);
  EXPECT_LT((m.omega - Eigen::Vector3d(0.2, -0.4, 3.0)).norm(), 1e-12);
  EXPECT_LT((m.velocity - Eigen::Vector3d(6.0, 0.5, 0.0)).norm(), 1e-12);
  // Leaning forward (pitch) does not change the heading; the root-frame vectors tilt with it.
  character::set_quat(
      q, 3,
      Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())));
  const RootMotion lean = root_motion(q, qd);
  const Eigen::Vector3d expected = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) * Eigen::Vector3d(6.0, 0.5, 0.0);
  EXPECT_LT((lean.velocity - expected).norm(), 1e-12);
}

// The step at which the rule fires on a sequence of control steps at 30 Hz (reference clock from
// `start`, accumulated as CharacterEnv does), with the take-off foot down on the steps in `single`.
int handover_step(const TakeoffCondition& c, double start, const std::vector<int>& single, int steps = 100) {
  double t = start;
  for (int k = 1; k <= steps; ++k) {
    t += 1.0 / 30.0;
    const bool down = std::find(single.begin(), single.end(), k) != single.end();
    if (takeoff_reached(c, t, down, !down)) return k;
  }
  return -1;
}

TEST(RunupHandOver, FiresExactlyAtTheTakeoffTimeWithoutSingleSupport) {
  const TakeoffCondition c{.takeoff_time_s = 1.0, .window_s = 0.2};
  EXPECT_EQ(handover_step(c, 0.0, {}), 30);  // t = 30/30 s: not step 29, not step 31
  EXPECT_EQ(handover_step(c, 0.5, {}), 15);  // an RSI start half-way in
  EXPECT_FALSE(takeoff_reached(c, 1.0 - 1.0 / 30.0, false, false));
  EXPECT_TRUE(takeoff_reached(c, 1.0, false, true));
}

TEST(RunupHandOver, FiresAtTheFirstSingleSupportStepInTheWindow) {
  const TakeoffCondition c{.takeoff_time_s = 1.0, .window_s = 0.2};  // window: steps 24..30
  EXPECT_EQ(handover_step(c, 0.0, {10, 20, 23, 26, 27}), 26);        // 23 is before the window
  EXPECT_EQ(handover_step(c, 0.0, {24}), 24);                        // the window's first step
  EXPECT_EQ(handover_step(c, 0.0, {31}), 30);                        // after the time: it already fired
  EXPECT_FALSE(takeoff_reached(c, 0.9, true, true));                 // both feet down: not single support
  EXPECT_FALSE(takeoff_reached(c, 0.9, false, false));               // in flight
  EXPECT_TRUE(takeoff_reached(c, 0.9, true, false));
  const TakeoffCondition exact{.takeoff_time_s = 1.0, .window_s = 0.0};
  EXPECT_EQ(handover_step(exact, 0.0, {25, 29}), 30);
}

}  // namespace
}  // namespace podium::tasks::jump
