#include "podium/learn/sac.h"

#include <gtest/gtest.h>

#include <cmath>

#include "podium/base/error.h"
#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"

namespace podium::learn {
namespace {

VecEnv pendulums(std::uint64_t seed) {
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(std::make_unique<Pendulum>());
  return VecEnv(std::move(envs), 1, seed);
}

TEST(Sac, ActionsStayInsideTheBoundAfterItChanges) {
  Pendulum env;
  SacConfig c;
  c.warmup_steps = 50;
  c.batch_size = 16;
  Sac sac(c, env.observation_space(), env.action_space(), 1);
  auto envs = pendulums(1);
  sac.train_until(envs, 120);
  sac.set_action_bound(0.25);  // pendulum torque limit 2 N·m -> |u| ≤ 0.5 N·m
  env.seed(2);
  std::vector<double> obs, action(1);
  env.reset(obs);
  double largest = 0.0;
  for (int i = 0; i < 200; ++i) {
    obs[2] = 8.0 * std::sin(i);  // sweep the state so the policy would like large torques
    sac.act(obs, action, i % 2 == 0);
    largest = std::max(largest, std::abs(action[0]));
  }
  EXPECT_LE(largest, 0.5 + 1e-6);
  EXPECT_GT(largest, 0.0);
  EXPECT_THROW(sac.set_action_bound(1.5), base::UserError);
  EXPECT_THROW(sac.set_action_bound(0.0), base::UserError);
}

TEST(Sac, TemperatureAdaptsAndReplayFills) {
  Pendulum env;
  SacConfig c;
  c.warmup_steps = 64;
  c.batch_size = 32;
  Sac sac(c, env.observation_space(), env.action_space(), 3);
  auto envs = pendulums(3);
  sac.train_until(envs, 300);
  EXPECT_EQ(sac.replay_size(), 300);
  EXPECT_NE(sac.alpha(), c.initial_alpha);
}

TEST(Sac, ConfigRejectsUnknownAndMistypedFields) {
  EXPECT_THROW(SacConfig::from_json({{"batch", 3}}), base::UserError);
  EXPECT_THROW(SacConfig::from_json({{"batch_size", "big"}}), base::UserError);
  const SacConfig paper = SacConfig::paper();
  EXPECT_EQ(SacConfig::from_json(paper.to_json()).to_json(), paper.to_json());
  EXPECT_EQ(paper.hidden, (std::vector<int>{1024, 1024}));
  EXPECT_EQ(paper.batch_size, 1024);
}

TEST(Ppo, SigmaAnnealsLinearlyAndConfigRoundTrips) {
  Pendulum env;
  PpoConfig c;
  c.rollout_steps = 50;
  c.sigma_start = 0.5;
  c.sigma_end = 0.1;
  c.sigma_anneal_steps = 200;
  Ppo ppo(c, env.observation_space(), env.action_space(), 1);
  EXPECT_DOUBLE_EQ(ppo.sigma(), 0.5);
  auto envs = pendulums(4);
  ppo.train_until(envs, 100);
  EXPECT_NEAR(ppo.sigma(), 0.3, 1e-12);
  ppo.train_until(envs, 300);
  EXPECT_DOUBLE_EQ(ppo.sigma(), 0.1);
  EXPECT_EQ(PpoConfig::from_json(PpoConfig::paper().to_json()).to_json(), PpoConfig::paper().to_json());
  EXPECT_THROW(PpoConfig::from_json({{"clip_range", 0.1}}), base::UserError);
}

TEST(MakeLearner, BuildsPresetsWithOverridesAndRejectsBadSpecs) {
  Pendulum env;
  const auto obs = env.observation_space(), act = env.action_space();
  auto ppo = make_learner({{"algorithm", "ppo"}, {"config", {{"hidden", {8}}}}}, obs, act, 1);
  EXPECT_EQ(ppo->name(), "ppo");
  EXPECT_EQ(ppo->parameters().size(), std::size_t(3 * 8 + 8 + 8 * 1 + 1 + 3 * 8 + 8 + 8 + 1));  // policy + value
  auto sac = make_learner({{"algorithm", "sac"}, {"preset", "paper"}, {"config", {{"hidden", {4}}}}}, obs, act, 1);
  EXPECT_EQ(sac->name(), "sac");
  EXPECT_THROW(make_learner({{"algorithm", "ddpg"}}, obs, act, 1), base::UserError);
  EXPECT_THROW(make_learner({{"algorithm", "sac"}, {"preset", "huge"}}, obs, act, 1), base::UserError);
  EXPECT_THROW(make_learner({{"algorithm", "sac"}, {"config", {{"gama", 0.9}}}}, obs, act, 1), base::UserError);
  EXPECT_THROW(make_learner({{"algorithm", "ppo"}, {"seed", 3}}, obs, act, 1), base::UserError);
}

TEST(Blas, FindsTheLoadedLibraryAndRecognisesTheReferenceOne) {
  Pendulum env;
  Ppo ppo(PpoConfig{}, env.observation_space(), env.action_space(), 1);  // loads libtorch's BLAS
  const std::string blas = active_blas_library();
  EXPECT_FALSE(blas.empty());
  std::printf("active BLAS: %s%s\n", blas.c_str(), is_reference_blas(blas) ? " (reference: slow)" : "");
  EXPECT_TRUE(is_reference_blas("/usr/lib/x86_64-linux-gnu/blas/libblas.so.3.11.0"));
  EXPECT_FALSE(is_reference_blas("/usr/lib/x86_64-linux-gnu/openblas-pthread/libblas.so.3"));
}

}  // namespace
}  // namespace podium::learn
