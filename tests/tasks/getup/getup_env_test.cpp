// The get-up environment (seed §4–5, §7) on real Bullet: episode length, the facing-invariant
// s_weak, the per-episode strength β̂ as SAC's action bound, and exact replay of a saved start.
#include "getup_env.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "podium/base/error.h"

namespace podium::tasks::getup {
namespace {

EnvSettings short_falls() {
  EnvSettings s;
  s.fall.control_steps = 20;
  return s;
}

TEST(GetupEnv, EpisodesRunTheirFullLengthWithoutEarlyTermination) {
  GetupEnv env(EnvSettings{}, std::make_shared<double>(1.0), true);
  env.seed(3);
  std::vector<double> observation;
  env.reset(observation);
  EXPECT_EQ(observation.size(), env.observation_space().size());
  // angles, velocities, the root's velocity, head, COM, effectors, torso, β̂
  EXPECT_EQ(observation.size(), 21u + 21u + 6u + 1u + 4u + 12u + 3u + 1u);
  const std::vector<double> zero(env.action_space().size(), 0.0);
  learn::StepResult step;
  int steps = 0;
  do {
    env.step(zero, step);
    ++steps;
    EXPECT_FALSE(step.terminated) << "at step " << steps;
    EXPECT_GE(step.reward, 0.0);
    EXPECT_LE(step.reward, 1.0);
  } while (!step.truncated);
  EXPECT_EQ(steps, 250);
  // A limp ragdoll lies on the ground: the head is far below r_h's bound.
  EXPECT_LT(env.weak().head_height_m, 0.6);
}

TEST(GetupEnv, ObservationIgnoresWhereTheCharacterFaces) {
  GetupEnv env(short_falls(), std::make_shared<double>(1.0), true);
  env.seed(5);
  std::vector<double> first, turned;
  env.reset(first);
  const learn::StepResult step = [&] {
    learn::StepResult r;
    env.step(std::vector<double>(env.action_space().size(), 0.3), r);
    return r;
  }();
  first = step.observation;
  // Turn the whole state about the vertical through the origin and move it on the ground; root
  // velocities are in the root frame, so q̇ is unchanged.
  Eigen::VectorXd q = env.world().data().q;
  const Eigen::VectorXd qd = env.world().data().qd;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond root(q(3), q(4), q(5), q(6));
  const Eigen::Quaterniond turned_root = turn * root;
  q.head<3>() = turn * q.head<3>() + Eigen::Vector3d(1.5, -0.7, 0.0);
  q(3) = turned_root.w(), q(4) = turned_root.x(), q(5) = turned_root.y(), q(6) = turned_root.z();
  env.world().set_state(q, qd);
  env.observe(turned);
  ASSERT_EQ(first.size(), turned.size());
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_NEAR(first[i], turned[i], 1e-9) << "observation entry " << i;
}

TEST(GetupEnv, StrengthIsDrawnPerEpisodeAndBoundsTheActions) {
  const auto beta = std::make_shared<double>(0.8);
  GetupEnv test(short_falls(), beta, false);
  std::vector<double> observation;
  test.seed(1);
  test.reset(observation);
  EXPECT_EQ(test.action_scale(), 0.8);
  EXPECT_EQ(observation.back(), 0.8);  // β̂ is the observation's last entry

  GetupEnv train(short_falls(), beta, true);
  train.seed(2);
  double sum = 0.0, min = 1.0, max = 0.0;
  for (int e = 0; e < 8; ++e) {
    train.reset(observation);
    EXPECT_EQ(observation.back(), train.action_scale());
    sum += train.action_scale(), min = std::min(min, train.action_scale()), max = std::max(max, train.action_scale());
  }
  EXPECT_LT(min, max);                  // drawn per episode
  EXPECT_NEAR(sum / 8, 0.8, 3 * 0.04);  // around β^i with ε = 0.04
  *beta = 1.0;
  for (int e = 0; e < 8; ++e) {
    train.reset(observation);
    EXPECT_LE(train.action_scale(), 1.0);  // clipped: SAC's bound β̂ must stay in (0, 1]
  }
}

TEST(GetupEnv, TorquesAreTheActionTimesTheTorqueLimits) {
  GetupEnv env(short_falls(), std::make_shared<double>(0.7), false);
  env.seed(4);
  std::vector<double> observation;
  env.reset(observation);
  // SAC already bounds the action by β̂ (action_scale); the torque map must not scale it again.
  const std::vector<double> action(env.action_space().size(), -0.5);
  learn::StepResult step;
  env.step(action, step);
  const auto& limits = env.model().torque_limits();
  for (int i = 6; i < env.model().nv(); ++i) EXPECT_DOUBLE_EQ(env.world().data().tau(i), -0.5 * limits(i)) << "DoF " << i;
}

TEST(GetupEnv, ASavedEpisodeStartReplaysBitwise) {
  const auto beta = std::make_shared<double>(0.9);
  GetupEnv original(short_falls(), beta, true);
  original.seed(11);
  std::vector<double> observation, restored_observation;
  original.reset(observation);
  const auto state = original.save_state();
  ASSERT_TRUE(state.has_value());

  GetupEnv restored(short_falls(), beta, true);
  restored.seed(99);
  restored.reset(restored_observation);  // another episode first
  restored.load_state(*state);
  restored.observe(restored_observation);
  EXPECT_EQ(restored.action_scale(), original.action_scale());
  EXPECT_EQ(restored_observation, observation);
  learn::StepResult a, b;
  for (int t = 0; t < 30; ++t) {
    std::vector<double> action(original.action_space().size());
    for (std::size_t j = 0; j < action.size(); ++j) action[j] = 0.5 * std::sin(0.3 * t + static_cast<double>(j));
    original.step(action, a);
    restored.step(action, b);
    ASSERT_EQ(a.observation, b.observation) << "step " << t;
    ASSERT_EQ(a.reward, b.reward) << "step " << t;
  }
}

// The seed repository's env.py reset: each of the fall's control steps is a transition under a
// zero action with its reward, from the release to the episode's first state.
TEST(GetupEnv, TheFallsStepsAreTransitionsUnderZeroActions) {
  GetupEnv env(EnvSettings{}, std::make_shared<double>(0.8), true);
  env.seed(21);
  std::vector<double> observation;
  env.reset(observation);
  const auto fall = env.start_transitions();
  ASSERT_EQ(fall.size(), 80u);
  EXPECT_EQ(fall.back().next_observation, observation);
  const double first_head = fall.front().observation[21 + 21 + 6];  // the head height, after q, q̇, root velocity
  EXPECT_GT(first_head, 0.9);                                       // released with the root at 1.5 m
  EXPECT_LT(observation[21 + 21 + 6], 0.6);                         // lying at the end
  for (std::size_t k = 0; k < fall.size(); ++k) {
    EXPECT_EQ(fall[k].action, std::vector<double>(env.action_space().size(), 0.0)) << k;
    EXPECT_FALSE(fall[k].terminated) << k;
    EXPECT_GE(fall[k].reward, 0.0) << k;
    EXPECT_LE(fall[k].reward, 1.0) << k;
    if (k > 0) {
      EXPECT_EQ(fall[k].observation, fall[k - 1].next_observation) << k;
    }
  }
  EXPECT_DOUBLE_EQ(fall.back().reward, reward_weak(env.weak()));  // R_weak of the state it ends in
  // Recording changes nothing in the episode: the same fall without it ends in the same state.
  EnvSettings quiet;
  quiet.fall_transitions = false;
  GetupEnv other(quiet, std::make_shared<double>(0.8), true);
  other.seed(21);
  std::vector<double> other_observation;
  other.reset(other_observation);
  EXPECT_TRUE(other.start_transitions().empty());
  EXPECT_EQ(other_observation, observation);
}

// §7's text's fall, a ~ N(0, 0.1) in torque limits: each transition carries the action it applied.
TEST(GetupEnv, ANoisyFallsTransitionsCarryItsActions) {
  EnvSettings noisy;
  noisy.fall.action_sigma = 0.1;
  GetupEnv env(noisy, std::make_shared<double>(1.0), true);
  env.seed(22);
  std::vector<double> observation;
  env.reset(observation);
  double sum_sq = 0.0;
  std::size_t n = 0;
  for (const learn::Transition& t : env.start_transitions())
    for (double a : t.action) {
      EXPECT_LE(std::abs(a), 1.0);
      sum_sq += a * a, ++n;
    }
  ASSERT_EQ(n, 80u * env.action_space().size());
  EXPECT_NEAR(std::sqrt(sum_sq / double(n)), 0.1, 0.01);  // 1680 draws of N(0, 0.1)
}

}  // namespace
}  // namespace podium::tasks::getup

namespace podium::tasks::getup {
namespace {

// §7's casts: the locked elbow and knee keep their angle through a fall under random torques.
TEST(GetupVariants, CastsKeepTheirJointAngles) {
  EnvSettings s = short_falls();
  s.variant = "casts";
  GetupEnv env(s, std::make_shared<double>(1.0), true);
  env.seed(5);
  std::vector<double> observation;
  env.reset(observation);
  const sim::CharacterModel& model = env.model();
  const std::vector<double> push(env.action_space().size(), 0.8);
  learn::StepResult step;
  for (int i = 0; i < 40; ++i) {
    env.step(push, step);
    for (const char* joint : {"elbow_left", "knee_right"}) {
      const sim::Link& link = model.link(joint);
      EXPECT_NEAR(env.world().data().q[link.q_index], 0.0, 0.02) << joint << " at step " << i;
    }
  }
}

TEST(GetupVariants, MissingArmRemovesTheLeftArmAndUnknownNamesFail) {
  EnvSettings s;
  s.variant = "missing_arm";
  GetupEnv env(s, std::make_shared<double>(1.0), true);
  EXPECT_EQ(env.model().find_body("upper_arm_left"), -1);
  EXPECT_EQ(env.model().find_link("elbow_left"), -1);
  EXPECT_NE(env.model().find_link("elbow_right"), -1);
  EXPECT_THROW(variant_edits("two_heads"), base::UserError);
}

}  // namespace
}  // namespace podium::tasks::getup
