// The jump rules (thesis §3.6.1) on real Bullet with scripted states: success on landing on the
// block clear of the wall, each failure, the head-first landing's r_safety.
#include <gtest/gtest.h>

#include <numbers>

#include "jump_test_util.h"

namespace podium::tasks::jump {
namespace {

using testing::place;
using testing::settings;
using testing::step_until_decided;

// At z = 0.5 m with the bar across the run (α = π/2): the wall's near face at x = 1.2 m, 5 cm
// thick; the block from x = 1.27 m to 5.27 m, its top at 2 cm.
const double kStanding = sim::load_shipped_model("athlete")->standing_pose()(2);  // the athlete's standing root height

TEST(JumpRules, LandingOnTheBlockClearOfTheWallSucceeds) {
  JumpEnv env(settings());
  std::vector<double> obs;
  env.reset(obs);
  place(env, {3.0, 0.0, kStanding + 0.02 + 0.01});  // feet 1 cm above the block
  const learn::StepResult last = step_until_decided(env);
  EXPECT_EQ(env.outcome(), Outcome::success) << env.outcome_reason();
  EXPECT_TRUE(last.terminated);
  EXPECT_EQ(env.outcome_reason(), "landed on the block");
  EXPECT_DOUBLE_EQ(env.reward_terms().safety, 1.0);
  EXPECT_DOUBLE_EQ(env.reward_terms().naturalness, 1.0);  // plain targets: no offsets
  EXPECT_GT(last.reward, 0.95);                           // r_ω of a near-still landing
  EXPECT_DOUBLE_EQ(last.reward, env.reward_terms().total());
  EXPECT_EQ(last.info[0], 1.0);  // success
}

TEST(JumpRules, HeadFirstLandingGivesSafetySevenTenths) {
  JumpEnv env(settings());
  std::vector<double> obs;
  env.reset(obs);
  // Upside down: the head top (0.866 m from the root) lowest, 1 cm above the block.
  place(env, {3.0, 0.0, 0.02 + 0.866 + 0.01}, Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY())));
  const learn::StepResult last = step_until_decided(env);
  ASSERT_EQ(env.outcome(), Outcome::success) << env.outcome_reason();
  EXPECT_EQ(env.outcome_reason(), "landed on the block head first");
  EXPECT_DOUBLE_EQ(env.reward_terms().safety, 0.7);
  EXPECT_NEAR(last.reward, 0.7 * env.reward_terms().omega, 1e-12);
  EXPECT_EQ(last.info[2], 1.0);  // head_first
}

TEST(JumpRules, LandingWithinClearanceOfTheWallIsNotYetASuccess) {
  JumpEnv env(settings());
  std::vector<double> obs;
  env.reset(obs);
  place(env, {1.4, 0.0, kStanding + 0.02 + 0.01});  // on the block, but the body 10–20 cm from the wall
  learn::StepResult out;
  env.step(testing::hold_pose(env), out);
  env.step(testing::hold_pose(env), out);
  ASSERT_TRUE(env.features().touches(env.takeoff_foot(), sim::Contact::Partner::prop, env.suite().block_prop));
  EXPECT_NE(env.outcome(), Outcome::success);
}

TEST(JumpRules, TouchingTheWallFails) {
  JumpEnv env(settings());
  std::vector<double> obs;
  env.reset(obs);
  place(env, {1.225, 0.0, kStanding + 0.5 + 0.005});  // feet 5 mm above the wall's top, over its mid-plane
  const learn::StepResult last = step_until_decided(env);
  EXPECT_EQ(env.outcome(), Outcome::touched_obstacle) << env.outcome_reason();
  EXPECT_NE(env.outcome_reason().find("touched the bar"), std::string::npos) << env.outcome_reason();
  EXPECT_TRUE(last.terminated);
  EXPECT_EQ(last.reward, 0.0);
}

TEST(JumpRules, TouchingTheObstacleBoxFails) {
  JumpEnv env(settings(JumpKind::obstacle, 1.0));
  std::vector<double> obs;
  env.reset(obs);
  place(env, {1.5, 0.0, kStanding + 0.5 + 0.005});  // feet just above the 50 cm box (x 1.0 … 2.0)
  step_until_decided(env);
  EXPECT_EQ(env.outcome(), Outcome::touched_obstacle);
  EXPECT_NE(env.outcome_reason().find("touched the obstacle"), std::string::npos) << env.outcome_reason();
}

TEST(JumpRules, ABodyOtherThanTheTakeoffFootOnTheGroundFails) {
  JumpEnv env(settings());
  std::vector<double> obs;
  env.reset(obs);
  place(env, {-1.0, 0.0, kStanding});  // standing on both feet before the bar
  const learn::StepResult last = step_until_decided(env, 1);
  EXPECT_EQ(env.outcome(), Outcome::touched_ground);
  EXPECT_EQ(env.outcome_reason(), "left_foot touched the ground");
  EXPECT_TRUE(last.terminated);
  EXPECT_EQ(last.reward, 0.0);
}

TEST(JumpRules, TheTakeoffFootAloneMayTouchTheGround) {
  JumpSettings s = settings();
  s.layout.wall_distance_m = 3.0;  // the swing foot reaches 1.2 m within 0.2 s at 6 m/s
  JumpEnv env(s);
  std::vector<double> obs;
  env.reset(obs);  // the take-off state: the right foot on the ground, the left leg driven up
  EXPECT_TRUE(env.features().touches(env.takeoff_foot(), sim::Contact::Partner::ground));
  learn::StepResult out;
  env.step(testing::hold_pose(env), out);
  EXPECT_EQ(env.outcome(), Outcome::in_flight) << env.outcome_reason();
  EXPECT_FALSE(out.terminated);
  EXPECT_EQ(out.reward, 0.0);  // sparse: nothing before the end
}

TEST(JumpRules, NoSuccessTwoSecondsAfterTakeoffFails) {
  JumpEnv env(settings());  // 10 Hz at z = 0.5
  std::vector<double> obs;
  env.reset(obs);
  place(env, {-5.0, 0.0, 30.0});  // falls 19.6 m in 2 s: still in the air
  learn::StepResult out;
  int steps = 0;
  do {
    env.step(testing::hold_pose(env), out);
    ++steps;
  } while (!out.terminated && !out.truncated && steps < 100);
  EXPECT_EQ(steps, 20);
  EXPECT_TRUE(out.terminated);
  EXPECT_FALSE(out.truncated);
  EXPECT_EQ(env.outcome(), Outcome::timed_out);
  EXPECT_EQ(env.outcome_reason(), "no landing 2 s after take-off");
  EXPECT_EQ(out.reward, 0.0);
}

}  // namespace
}  // namespace podium::tasks::jump
