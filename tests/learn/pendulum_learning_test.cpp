// Acceptance: PPO and SAC learn the pendulum swing-up (label `learning`). Seeds 100-104 were
// never used for tuning (that was seeds 0-4).
#include <gtest/gtest.h>

#include <cstdio>
#include <numeric>

#include "learning_settings.h"
#include "podium/base/rng.h"
#include "podium/learn/classic_control.h"

namespace podium::learn {
namespace {

constexpr double kThreshold = -200.0;  // mean final evaluation return, Gym's scale
constexpr double kMargin = 500.0;      // required gain over the untrained policy

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }

double evaluate_mean(Learner& learner, std::uint64_t seed) {
  Pendulum env;
  env.seed(base::derive_seed(seed, 7));
  return mean(evaluate(learner, env, 10));
}

VecEnv pendulums(int copies, std::uint64_t seed) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < copies; ++i) envs.push_back(std::make_unique<Pendulum>());
  return VecEnv(std::move(envs), 2, seed);
}

template <class MakeAndTrain>
void expect_learns(const char* name, MakeAndTrain make_and_train) {
  int passed = 0;
  for (std::uint64_t seed = 100; seed < 105; ++seed) {
    const auto [initial, final_return] = make_and_train(seed);
    const bool ok = final_return >= kThreshold && final_return - initial >= kMargin;
    passed += ok;
    std::printf("%s seed %llu: initial %.1f -> final %.1f %s\n", name, static_cast<unsigned long long>(seed), initial,
                final_return, ok ? "ok" : "below threshold");
    std::fflush(stdout);
  }
  EXPECT_GE(passed, 4) << name << " reached " << kThreshold << " in " << passed << " of 5 seeds";
}

TEST(PendulumLearning, PpoReachesMinus200InFourOfFiveSeeds) {
  expect_learns("ppo", [](std::uint64_t seed) {
    Pendulum probe;
    Ppo ppo(testing::pendulum_ppo(), probe.observation_space(), probe.action_space(), seed);
    const double initial = evaluate_mean(ppo, seed);
    auto envs = pendulums(testing::kPendulumPpoCopies, seed);
    ppo.train_until(envs, testing::kPendulumPpoSteps);
    return std::pair{initial, evaluate_mean(ppo, seed)};
  });
}

TEST(PendulumLearning, SacReachesMinus200InFourOfFiveSeeds) {
  expect_learns("sac", [](std::uint64_t seed) {
    Pendulum probe;
    Sac sac(testing::pendulum_sac(), probe.observation_space(), probe.action_space(), seed);
    const double initial = evaluate_mean(sac, seed);
    auto envs = pendulums(1, seed);
    sac.train_until(envs, testing::kPendulumSacSteps);
    return std::pair{initial, evaluate_mean(sac, seed)};
  });
}

}  // namespace
}  // namespace podium::learn
