#include "podium/learn/classic_control.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace podium::learn {
namespace {

TEST(Pendulum, FollowsGymEquationsForOneStep) {
  Pendulum env;
  env.seed(3);
  std::vector<double> obs;
  env.reset(obs);
  const double th = std::atan2(obs[1], obs[0]), thdot = obs[2];
  StepResult r;
  const double u = 1.5;
  env.step(std::vector<double>{u}, r);
  const double expected_reward = -(th * th + 0.1 * thdot * thdot + 0.001 * u * u);
  const double new_thdot = thdot + (15.0 * std::sin(th) + 3.0 * u) * 0.05;
  EXPECT_NEAR(r.reward, expected_reward, 1e-12);
  EXPECT_NEAR(r.observation[2], new_thdot, 1e-12);
  EXPECT_NEAR(std::atan2(r.observation[1], r.observation[0]), th + new_thdot * 0.05, 1e-12);
}

TEST(Pendulum, TruncatesAfter200StepsWithoutTerminating) {
  Pendulum env;
  env.seed(1);
  std::vector<double> obs;
  env.reset(obs);
  StepResult r;
  for (int t = 1; t <= Pendulum::kEpisodeSteps; ++t) {
    env.step(std::vector<double>{0.0}, r);
    EXPECT_FALSE(r.terminated);
    EXPECT_EQ(r.truncated, t == Pendulum::kEpisodeSteps);
  }
}

TEST(Pendulum, ClipsTorqueAndSpeed) {
  Pendulum env;
  env.seed(2);
  std::vector<double> obs;
  env.reset(obs);
  StepResult r;
  for (int t = 0; t < 100; ++t) {
    env.step(std::vector<double>{100.0}, r);
    EXPECT_LE(std::abs(r.observation[2]), 8.0);
    EXPECT_GE(r.reward, -(std::numbers::pi * std::numbers::pi + 0.1 * 64 + 0.001 * 4) - 1e-12);
  }
}

TEST(Pendulum, SaveLoadStateContinuesIdentically) {
  Pendulum a, b;
  a.seed(5);
  b.seed(99);
  std::vector<double> obs;
  a.reset(obs);
  StepResult ra, rb;
  a.step(std::vector<double>{0.3}, ra);
  b.load_state(*a.save_state());
  a.step(std::vector<double>{-0.7}, ra);
  b.step(std::vector<double>{-0.7}, rb);
  EXPECT_EQ(ra.observation, rb.observation);
  std::vector<double> oa, ob;
  a.reset(oa);
  b.reset(ob);
  EXPECT_EQ(oa, ob);
}

TEST(CartPole, TerminatesWhenThePoleFalls) {
  CartPole env;
  env.seed(4);
  std::vector<double> obs;
  env.reset(obs);
  StepResult r;
  int steps = 0;
  do {
    env.step(std::vector<double>{1.0}, r);
    ++steps;
  } while (!r.terminated && !r.truncated);
  EXPECT_TRUE(r.terminated);
  EXPECT_LT(steps, 100);  // full push one way: the pole falls within a second or two
  EXPECT_TRUE(std::abs(r.observation[2]) > 12 * std::numbers::pi / 180 || std::abs(r.observation[0]) > 2.4);
}

TEST(CartPole, BalancedPoleTruncatesAt500Steps) {
  CartPole env;
  env.seed(6);
  std::vector<double> obs;
  env.reset(obs);
  StepResult r;
  int steps = 0;
  do {
    // A PD controller on the pole angle and cart position keeps it up.
    const double a = 10.0 * obs[2] + 2.0 * obs[3] + 0.1 * obs[0] + 0.3 * obs[1];
    env.step(std::vector<double>{a}, r);
    obs = r.observation;
    ++steps;
  } while (!r.terminated && !r.truncated);
  EXPECT_TRUE(r.truncated);
  EXPECT_EQ(steps, CartPole::kEpisodeSteps);
}

}  // namespace
}  // namespace podium::learn
