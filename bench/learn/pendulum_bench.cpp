// Trains PPO or SAC on the pendulum swing-up and prints the learning curve, wall-time split
// (rollout vs update) and the final deterministic evaluation.
// Usage: learn_pendulum_bench ppo|sac SEED ENV_STEPS [COPIES] [THREADS] [CONFIG_JSON]
// e.g. the update-to-data ratio: learn_pendulum_bench sac 1 6000 1 1 '{"updates_per_step": 0.25}'
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

using namespace podium::learn;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s ppo|sac SEED ENV_STEPS [COPIES] [THREADS] [CONFIG_JSON]\n", argv[0]);
    return 2;
  }
  const std::string algo = argv[1];
  const std::uint64_t seed = std::strtoull(argv[2], nullptr, 10);
  const std::int64_t steps = std::strtoll(argv[3], nullptr, 10);
  const int copies = argc > 4 ? std::atoi(argv[4]) : 8;
  const int threads = argc > 5 ? std::atoi(argv[5]) : 1;
  const auto config = argc > 6 ? podium::base::Json::parse(argv[6]) : podium::base::Json::object();
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < copies; ++i) envs.push_back(std::make_unique<Pendulum>());
  VecEnv vec(std::move(envs), threads, seed);
  Pendulum probe;
  std::unique_ptr<Learner> learner;
  if (algo == "ppo") {
    learner = std::make_unique<Ppo>(PpoConfig::from_json(config), probe.observation_space(), probe.action_space(), seed);
  } else if (algo == "sac") {
    learner = std::make_unique<Sac>(SacConfig::from_json(config), probe.observation_space(), probe.action_space(), seed);
  } else {
    std::fprintf(stderr, "unknown algorithm %s\n", algo.c_str());
    return 2;
  }
  double rollout_s = 0, update_s = 0;
  const auto t0 = std::chrono::steady_clock::now();
  learner->train_until(vec, steps, [&](const TrainStats& s) {
    rollout_s += s.rollout_seconds;
    update_s += s.update_seconds;
    std::printf("steps %lld return %.1f (%zu episodes)\n", static_cast<long long>(s.env_steps), s.mean_return, s.episodes);
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Pendulum eval_env;
  eval_env.seed(seed + 1000);
  const auto returns = evaluate(*learner, eval_env, 10);
  double mean = 0;
  for (double r : returns) mean += r / double(returns.size());
  std::printf("%s seed %llu: final evaluation mean return %.1f over 10 episodes; wall %.1f s (rollout %.1f s, update %.1f s), %.0f env steps/s\n",
              algo.c_str(), static_cast<unsigned long long>(seed), mean, wall, rollout_s, update_s, double(steps) / wall);
  return 0;
}
