// Trains PPO or SAC on the pendulum swing-up and prints the learning curve, wall-time split
// (rollout vs update) and the final deterministic evaluation.
// Usage: learn_pendulum_bench ppo|sac SEED ENV_STEPS [COPIES] [THREADS] [CONFIG_JSON]
// e.g. the update-to-data ratio: learn_pendulum_bench sac 1 6000 1 1 '{"updates_per_step": 0.25}'
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "bench_args.h"
#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

using namespace podium::learn;

int main(int argc, char** argv) {
  long long seed_arg = 0, steps = 0, copies = 8, threads = 1;
  using podium::bench::whole_number;
  const std::string algo = argc > 1 ? argv[1] : "";
  if (argc < 4 || argc > 7 || (algo != "ppo" && algo != "sac") || !whole_number(argv[2], 0, seed_arg) ||
      !whole_number(argv[3], 1, steps) || (argc > 4 && !whole_number(argv[4], 1, copies)) ||
      (argc > 5 && !whole_number(argv[5], 1, threads))) {
    std::fprintf(stderr, "usage: %s ppo|sac SEED ENV_STEPS>0 [COPIES>0] [THREADS>0] [CONFIG_JSON]\n", argv[0]);
    return 2;
  }
  const auto seed = static_cast<std::uint64_t>(seed_arg);
  std::vector<std::unique_ptr<Env>> envs;
  for (long long i = 0; i < copies; ++i) envs.push_back(std::make_unique<Pendulum>());
  VecEnv vec(std::move(envs), static_cast<int>(threads), seed);
  Pendulum probe;
  std::unique_ptr<Learner> learner;
  try {
    const auto config = argc > 6 ? podium::base::Json::parse(argv[6]) : podium::base::Json::object();
    if (algo == "ppo")
      learner = std::make_unique<Ppo>(PpoConfig::from_json(config), probe.observation_space(), probe.action_space(), seed);
    else learner = std::make_unique<Sac>(SacConfig::from_json(config), probe.observation_space(), probe.action_space(), seed);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "learn_pendulum_bench: CONFIG_JSON: %s\n", error.what());
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
  std::printf(
      "%s seed %llu: final evaluation mean return %.1f over 10 episodes; wall %.1f s (rollout %.1f s, update %.1f s), %.0f env "
      "steps/s\n",
      algo.c_str(), static_cast<unsigned long long>(seed_arg), mean, wall, rollout_s, update_s, double(steps) / wall);
  return 0;
}
