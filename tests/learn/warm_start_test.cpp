// Warm starts: a learner started from another run's checkpoint or TorchScript export, under a
// different config, acts exactly like the source policy (first evaluation equal to 1e-9) and
// starts its own training afresh.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>

#include "podium/base/error.h"
#include "small_learners.h"

namespace podium::learn {
namespace {

namespace fs = std::filesystem;
using testing::pendulums;
using testing::temp_dir;

double first_evaluation(Learner& learner) {
  Pendulum env;
  env.seed(77);
  return evaluate(learner, env, 1).front();
}

// Number of parameters of an MLP in → hidden → out.
std::size_t mlp_size(std::size_t in, const std::vector<int>& hidden, std::size_t out) {
  std::size_t n = 0, width = in;
  for (int h : hidden) {
    n += width * std::size_t(h) + std::size_t(h);
    width = std::size_t(h);
  }
  return n + width * out + out;
}

std::string what_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const base::UserError& e) {
    return e.what();
  }
  return "";
}

PpoConfig source_ppo() {
  PpoConfig c;
  c.rollout_steps = 100;
  c.minibatch_size = 50;
  return c;
}

TEST(WarmStart, PpoFromCheckpointAndExportActsLikeTheSourceUnderAnotherConfig) {
  const fs::path dir = temp_dir("warm_ppo");
  Pendulum probe;
  Ppo source(source_ppo(), probe.observation_space(), probe.action_space(), 1);
  auto envs = pendulums(1);
  source.train_until(envs, 800);  // moves weights and normaliser away from their start
  source.save_checkpoint(dir / "source.ckpt", envs);
  source.export_torchscript(dir / "source.pt");
  const double source_return = first_evaluation(source);

  PpoConfig other;  // another learning rate, batch and σ schedule
  other.policy_lr_start = other.policy_lr_end = 1e-3;
  other.minibatch_size = 32;
  other.rollout_steps = 64;
  other.sigma_start = 0.3;
  const std::size_t policy_size = mlp_size(3, other.hidden, 1);
  for (const char* file : {"source.ckpt", "source.pt"}) {
    SCOPED_TRACE(file);
    Ppo warm(other, probe.observation_space(), probe.action_space(), 9);
    warm.warm_start(dir / file);
    EXPECT_NEAR(first_evaluation(warm), source_return, 1e-9);
    EXPECT_EQ(warm.env_steps(), 0);
    EXPECT_DOUBLE_EQ(warm.sigma(), 0.3);
    const auto p = warm.parameters(), q = source.parameters();
    EXPECT_TRUE(std::equal(p.begin(), p.begin() + long(policy_size), q.begin()));
    // The value network comes along from a checkpoint only.
    EXPECT_EQ(std::equal(p.begin() + long(policy_size), p.end(), q.begin() + long(policy_size)),
              std::string(file) == "source.ckpt");
    auto warm_envs = pendulums(3);
    warm.train_until(warm_envs, 128);  // trains under its own config from step 0
    EXPECT_EQ(warm.env_steps(), 128);
  }
  fs::remove_all(dir);
}

TEST(WarmStart, SacFromCheckpointAndExportActsLikeTheSourceWithFreshTrainingState) {
  const fs::path dir = temp_dir("warm_sac");
  Pendulum probe;
  auto envs = pendulums(2);
  const auto trained = testing::trained_sac(envs, 400);
  Sac& source = *trained;
  source.save_checkpoint(dir / "source.ckpt", envs);
  source.export_torchscript(dir / "source.pt");
  const double source_return = first_evaluation(source);

  SacConfig other = testing::small_sac();
  other.actor_lr = other.critic_lr = 3e-4;
  other.batch_size = 64;
  other.initial_alpha = 0.2;
  other.warmup_steps = 0;
  const std::size_t actor = mlp_size(3, other.hidden, 2), critic = mlp_size(4, other.hidden, 1);
  for (const char* file : {"source.ckpt", "source.pt"}) {
    SCOPED_TRACE(file);
    Sac warm(other, probe.observation_space(), probe.action_space(), 8);
    warm.warm_start(dir / file);
    EXPECT_NEAR(first_evaluation(warm), source_return, 1e-9);
    EXPECT_EQ(warm.env_steps(), 0);
    EXPECT_EQ(warm.replay_size(), 0);
    EXPECT_NEAR(warm.alpha(), 0.2, 1e-7);
    const auto p = warm.parameters(), q = source.parameters();
    EXPECT_TRUE(std::equal(p.begin(), p.begin() + long(actor), q.begin()));
    EXPECT_EQ(std::equal(p.begin() + long(actor), p.begin() + long(actor + 2 * critic), q.begin() + long(actor)),
              std::string(file) == "source.ckpt");
    auto warm_envs = pendulums(4);
    warm.train_until(warm_envs, 100);
    EXPECT_EQ(warm.replay_size(), 100);
  }
  fs::remove_all(dir);
}

TEST(WarmStart, RejectsAnotherAlgorithmShapeOrFileWithTheReason) {
  const fs::path dir = temp_dir("warm_errors");
  Pendulum probe;
  const auto obs = probe.observation_space(), act = probe.action_space();
  Ppo source(source_ppo(), obs, act, 1);
  source.export_torchscript(dir / "ppo.pt");

  Sac sac(SacConfig{}, obs, act, 1);
  EXPECT_TRUE(std::regex_search(what_of([&] { sac.warm_start(dir / "ppo.pt"); }),
                                std::regex("warm start from .*ppo.pt: algorithm is \"ppo\" there but \"sac\" here")));
  PpoConfig wider;
  wider.hidden = {32};
  Ppo ppo(wider, obs, act, 1);
  EXPECT_TRUE(std::regex_search(what_of([&] { ppo.warm_start(dir / "ppo.pt"); }),
                                std::regex("hidden is \\[64,64\\] there but \\[32\\] here")));
  PpoConfig raw;
  raw.normalize_observations = false;
  Ppo unnormalised(raw, obs, act, 1);
  EXPECT_TRUE(
      std::regex_search(what_of([&] { unnormalised.warm_start(dir / "ppo.pt"); }), std::regex("normalize_observations differs")));
  EXPECT_TRUE(std::regex_search(what_of([&] { ppo.warm_start(dir / "missing.pt"); }), std::regex("missing.pt does not exist")));
  std::ofstream(dir / "junk.pt") << "not a policy";
  EXPECT_TRUE(std::regex_search(what_of([&] { ppo.warm_start(dir / "junk.pt"); }), std::regex("junk.pt is not a torch archive")));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace podium::learn
