#pragma once
// The pendulum settings shared by the learning tests and the resume helper. Tuned on seeds 0-4
// (bench/learn/learn_pendulum_bench); the learning tests run seeds 100-104, never tuned on.
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

namespace podium::learn::testing {

inline PpoConfig pendulum_ppo() {
  PpoConfig c;  // 64-64 tanh, 10 epochs, clip 0.2, σ 0.5 → 0.1
  c.gamma = 0.95;
  c.reward_scale = 0.1;
  c.minibatch_size = 256;
  c.sigma_anneal_steps = 300'000;
  c.lr_anneal_steps = 300'000;
  c.policy_lr_end = 5e-5;
  c.value_lr_end = 2e-4;
  return c;
}
inline constexpr std::int64_t kPendulumPpoSteps = 300'000;
inline constexpr int kPendulumPpoCopies = 8;

inline SacConfig pendulum_sac() { return SacConfig::quick(); }
inline constexpr std::int64_t kPendulumSacSteps = 15'000;

}  // namespace podium::learn::testing
