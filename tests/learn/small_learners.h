#pragma once
// Pendulum copies and briefly trained learners shared by the learn unit tests that check what a
// trained policy becomes (a checkpoint, an export, a frozen policy, a warm start), not learning.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

namespace podium::learn::testing {

/// `copies` Pendulums stepped on one thread.
inline VecEnv pendulums(std::uint64_t seed, int copies = 2) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < copies; ++i) envs.push_back(std::make_unique<Pendulum>());
  return VecEnv(std::move(envs), 1, seed);
}

/// A fresh folder under the temp directory, named for the test binary's process.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("podium_learn_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

/// SAC with a normaliser: 100 warm-up steps, batch 32.
inline SacConfig small_sac() {
  SacConfig c;
  c.warmup_steps = 100;
  c.batch_size = 32;
  c.normalize_observations = true;
  return c;
}

/// small_sac() (seed 2) trained for `steps` on `envs`: weights and normaliser moved from their start.
inline std::unique_ptr<Sac> trained_sac(VecEnv& envs, std::int64_t steps) {
  Pendulum probe;
  auto sac = std::make_unique<Sac>(small_sac(), probe.observation_space(), probe.action_space(), 2);
  sac->train_until(envs, steps);
  return sac;
}

/// PPO with 100-step rollouts (seed 1) trained for `steps` on `envs`.
inline std::unique_ptr<Ppo> trained_ppo(VecEnv& envs, std::int64_t steps) {
  Pendulum probe;
  PpoConfig c;
  c.rollout_steps = 100;
  auto ppo = std::make_unique<Ppo>(c, probe.observation_space(), probe.action_space(), 1);
  ppo->train_until(envs, steps);
  return ppo;
}

}  // namespace podium::learn::testing
