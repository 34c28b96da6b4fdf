// The strategy feature (thesis §3.6.1) on scripted crossings: root poses set in the World, the
// COM read from it, the orientation interpolated to the step's crossing fraction.
#include "strategy_feature.h"

#include <gtest/gtest.h>

#include <numbers>

#include "jump_test_util.h"

namespace podium::tasks::jump {
namespace {

constexpr double kPi = std::numbers::pi;

// Puts the standing pose in the World with its root at `root`, pitched back by `lean` (rotation
// about −y tips the forward axis up), and returns the COM the World observes.
Eigen::Vector3d pose_at(JumpEnv& env, const Eigen::Vector3d& root, double lean, Eigen::Quaterniond& rotation) {
  rotation = Eigen::Quaterniond(Eigen::AngleAxisd(-lean, Eigen::Vector3d::UnitY()));
  testing::place(env, root, rotation);
  return env.world().observe().com;
}

TEST(StrategyFeature, AngleToUpIsInterpolatedToTheCrossing) {
  JumpEnv env(testing::settings(JumpKind::high_jump, 1.0));  // bar mid-plane at x = 1.225
  CrossingRecorder recorder(env.suite());
  recorder.reset();
  Eigen::Quaterniond before, after, at_start;
  recorder.observe(pose_at(env, {0.0, 0.0, 1.5}, 0.0, at_start), at_start);   // take-off: upright
  const Eigen::Vector3d c0 = pose_at(env, {1.0, 0.0, 1.6}, kPi / 3, before);  // leaning back 60°
  recorder.observe(c0, before);
  EXPECT_FALSE(recorder.crossed());
  const Eigen::Vector3d c1 = pose_at(env, {1.5, 0.0, 1.7}, kPi / 2, after);  // lying face up
  recorder.observe(c1, after);
  ASSERT_TRUE(recorder.crossed());
  const double s0 = env.suite().signed_distance(c0), s1 = env.suite().signed_distance(c1);
  ASSERT_LT(s0, 0.0);
  ASSERT_GT(s1, 0.0);
  const double t = -s0 / (s1 - s0);
  const double lean = kPi / 3 + t * (kPi / 2 - kPi / 3);
  EXPECT_NEAR(recorder.up_angle(), kPi / 2 - lean, 1e-9);  // the forward axis is lean below up's complement
  // Later steps do not move it.
  recorder.observe(pose_at(env, {3.0, 0.0, 0.5}, 0.0, after), after);
  EXPECT_NEAR(recorder.up_angle(), kPi / 2 - lean, 1e-9);
  // Stage 2 (α = π/2: the bar frame is the world frame): a rotation about −y by the lean.
  EXPECT_LT((recorder.bar_frame_rotation() - Eigen::Vector3d(0.0, -lean, 0.0)).norm(), 1e-9);
}

TEST(StrategyFeature, FacingDownReadsPiAndUprightHalfPi) {
  JumpEnv env(testing::settings());
  for (auto [lean, expected] : {std::pair{-kPi / 2, kPi}, {0.0, kPi / 2}, {kPi / 2, 0.0}}) {
    CrossingRecorder recorder(env.suite());
    recorder.reset();
    Eigen::Quaterniond r;
    recorder.observe(pose_at(env, {0.8, 0.0, 1.5}, lean, r), r);
    recorder.observe(pose_at(env, {1.6, 0.0, 1.5}, lean, r), r);
    ASSERT_TRUE(recorder.crossed());
    EXPECT_NEAR(recorder.up_angle(), expected, 1e-9) << "lean " << lean;
  }
}

TEST(StrategyFeature, BarFrameRotationIsRelativeToTheTurnedSuite) {
  JumpSettings s = testing::settings();
  s.takeoff_features = {0.0, 0.0, 0.0, 0.0};  // α = 0: bar along x, crossed towards +y
  JumpEnv env(s);
  CrossingRecorder recorder(env.suite());
  recorder.reset();
  const Eigen::Quaterniond facing_bar(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()));  // facing +y, over the bar
  testing::place(env, {0.0, 0.5, 1.5}, facing_bar);
  recorder.observe(env.world().observe().com, facing_bar);
  testing::place(env, {0.0, 2.0, 1.5}, facing_bar);
  recorder.observe(env.world().observe().com, facing_bar);
  ASSERT_TRUE(recorder.crossed());
  EXPECT_LT(recorder.bar_frame_rotation().norm(), 1e-9);  // no rotation relative to the bar
  EXPECT_NEAR(recorder.up_angle(), kPi / 2, 1e-9);
}

TEST(StrategyFeature, WithoutACrossingTheClosestApproachIsRead) {
  JumpEnv env(testing::settings());
  CrossingRecorder recorder(env.suite());
  recorder.reset();
  Eigen::Quaterniond r, closest;
  recorder.observe(pose_at(env, {0.0, 0.0, 1.5}, 0.0, r), r);
  recorder.observe(pose_at(env, {0.9, 0.0, 1.5}, kPi / 4, closest), closest);
  recorder.observe(pose_at(env, {0.3, 0.0, 1.5}, kPi / 2, r), r);  // fell back
  EXPECT_FALSE(recorder.crossed());
  EXPECT_NEAR(recorder.up_angle(), kPi / 4, 1e-9);
}

TEST(StrategyFeature, JumpEnvRecordsItEveryControlStep) {
  JumpEnv env(testing::settings());
  std::vector<double> obs;
  env.reset(obs);
  // In the air before the bar, moving over it at 8 m/s and turning face up about −y.
  Eigen::VectorXd q = env.model().standing_pose();
  q.head<3>() = Eigen::Vector3d(0.6, 0.0, 2.5);
  env.world().set_state_world(q, Eigen::Vector3d(0.0, -3.0, 0.0), Eigen::Vector3d(8.0, 0.0, 0.0),
                              Eigen::VectorXd::Zero(env.model().nv() - 6));
  learn::StepResult out;
  for (int i = 0; i < 3 && !out.terminated; ++i) env.step(testing::hold_pose(env), out);
  ASSERT_TRUE(env.crossing().crossed());
  // Between upright (π/2) and the pose after one 0.1 s step (turned 0.3 rad further up).
  EXPECT_LT(env.crossing().up_angle(), kPi / 2);
  EXPECT_GT(env.crossing().up_angle(), kPi / 2 - 0.6);
  EXPECT_DOUBLE_EQ(out.info[5], env.crossing().up_angle());
}

}  // namespace
}  // namespace podium::tasks::jump
