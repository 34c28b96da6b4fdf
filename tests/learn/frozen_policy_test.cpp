// FrozenPolicy: loaded from a checkpoint or an export, queried from two threads at once, it gives
// exactly the learner's deterministic actions.
#include "podium/learn/frozen_policy.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "small_learners.h"

namespace podium::learn {
namespace {

namespace fs = std::filesystem;
using testing::pendulums;
using testing::temp_dir;

std::vector<std::vector<double>> observations(std::uint64_t seed, int n) {
  base::Rng rng(seed);
  std::vector<std::vector<double>> out;
  for (int i = 0; i < n; ++i) out.push_back({rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-12.0, 12.0)});
  return out;
}

// Two threads each query `policy` for their own observations; every action must equal the
// learner's deterministic act().
void check_two_threads(Learner& learner, const FrozenPolicy& policy, double scale) {
  const auto obs_a = observations(1, 2000), obs_b = observations(2, 2000);
  auto expected = [&](const std::vector<std::vector<double>>& obs) {
    std::vector<double> out(obs.size());
    for (std::size_t i = 0; i < obs.size(); ++i) learner.act(obs[i], std::span<double>(&out[i], 1), true, scale);
    return out;
  };
  const auto want_a = expected(obs_a), want_b = expected(obs_b);
  std::vector<double> got_a(obs_a.size()), got_b(obs_b.size());
  auto query = [&](const std::vector<std::vector<double>>& obs, std::vector<double>& got) {
    for (std::size_t i = 0; i < obs.size(); ++i) policy.act(obs[i], std::span<double>(&got[i], 1), scale);
  };
  std::thread a(query, std::cref(obs_a), std::ref(got_a));
  std::thread b(query, std::cref(obs_b), std::ref(got_b));
  a.join();
  b.join();
  EXPECT_EQ(got_a, want_a);
  EXPECT_EQ(got_b, want_b);
}

TEST(FrozenPolicy, PpoFromCheckpointAndExportMatchesTheLearnerFromTwoThreads) {
  const fs::path dir = temp_dir("frozen_ppo");
  auto envs = pendulums(1);
  const auto ppo = testing::trained_ppo(envs, 400);
  ppo->save_checkpoint(dir / "p.ckpt", envs);
  ppo->export_torchscript(dir / "p.pt");
  for (const char* file : {"p.ckpt", "p.pt"}) {
    SCOPED_TRACE(file);
    const FrozenPolicy policy(dir / file);
    EXPECT_EQ(policy.algorithm(), "ppo");
    EXPECT_EQ(policy.observation_size(), 3u);
    EXPECT_EQ(policy.action_size(), 1u);
    check_two_threads(*ppo, policy, 1.0);
    check_two_threads(*ppo, policy, 0.6);  // a weaker character's box, as in getup's curriculum
    std::vector<double> action(1);
    EXPECT_THROW(policy.act(std::vector<double>{0.0, 1.0, 0.0}, action, 1.5), base::UserError);
    EXPECT_THROW(policy.act(std::vector<double>{0.0, 1.0}, action), base::UserError);
  }
  fs::remove_all(dir);
}

TEST(FrozenPolicy, SacWithBoundAndScaleMatchesTheLearnerFromTwoThreads) {
  const fs::path dir = temp_dir("frozen_sac");
  auto envs = pendulums(2);
  const auto sac = testing::trained_sac(envs, 300);
  sac->set_action_bound(0.8);
  sac->save_checkpoint(dir / "s.ckpt", envs);
  sac->export_torchscript(dir / "s.pt");
  for (const char* file : {"s.ckpt", "s.pt"}) {
    SCOPED_TRACE(file);
    const FrozenPolicy policy(dir / file);
    EXPECT_EQ(policy.algorithm(), "sac");
    check_two_threads(*sac, policy, 1.0);
    check_two_threads(*sac, policy, 0.6);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace podium::learn
