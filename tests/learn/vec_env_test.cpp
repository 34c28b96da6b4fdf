#include "podium/learn/vec_env.h"

#include <gtest/gtest.h>

#include "podium/base/error.h"
#include "podium/learn/classic_control.h"

namespace podium::learn {
namespace {

std::vector<std::unique_ptr<Env>> pendulums(int n) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(std::make_unique<Pendulum>());
  return envs;
}

// Runs 450 steps with actions that depend on the step and copy index; returns every observation.
std::vector<double> trajectory(int threads) {
  VecEnv envs(pendulums(5), threads, 42);
  std::vector<double> out;
  std::vector<double> actions(5);
  for (int t = 0; t < 450; ++t) {
    for (int i = 0; i < 5; ++i) actions[std::size_t(i)] = std::sin(0.1 * t + i);
    envs.step(actions);
    for (std::size_t i = 0; i < 5; ++i) {
      out.insert(out.end(), envs.observation(i).begin(), envs.observation(i).end());
      out.push_back(envs.result(i).reward);
    }
  }
  return out;
}

TEST(VecEnv, ResultsDoNotDependOnThreadCount) {
  const auto one = trajectory(1);
  EXPECT_EQ(one, trajectory(2));
  EXPECT_EQ(one, trajectory(3));
}

TEST(VecEnv, ResetsFinishedEpisodesAndReportsTheirReturns) {
  VecEnv envs(pendulums(3), 2, 7);
  std::vector<double> actions(3, 0.0);
  for (int t = 0; t < Pendulum::kEpisodeSteps - 1; ++t) envs.step(actions);
  EXPECT_TRUE(envs.take_finished_returns().empty());
  envs.step(actions);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(envs.result(i).truncated);
    // The result keeps the final observation; the runner already holds the next episode's first.
    EXPECT_NE(envs.result(i).observation, envs.observation(i));
  }
  const auto returns = envs.take_finished_returns();
  ASSERT_EQ(returns.size(), 3u);
  for (double r : returns) EXPECT_LT(r, 0.0);
}

TEST(VecEnv, SaveLoadStateContinuesIdentically) {
  VecEnv a(pendulums(4), 2, 11), b(pendulums(4), 1, 12);
  std::vector<double> actions(4, 0.5);
  for (int t = 0; t < 150; ++t) a.step(actions);
  b.load_state(a.save_state());
  for (int t = 0; t < 150; ++t) {
    a.step(actions);
    b.step(actions);
  }
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(a.observation(i), b.observation(i));
  EXPECT_EQ(a.take_finished_returns(), b.take_finished_returns());
}

TEST(VecEnv, RejectsWrongActionCount) {
  VecEnv envs(pendulums(2), 1, 0);
  EXPECT_THROW(envs.step(std::vector<double>(3, 0.0)), base::UserError);
}

}  // namespace
}  // namespace podium::learn
