#include "podium/learn/sac.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "podium/base/error.h"
#include "podium/base/rng.h"
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

// A pendulum whose strength s is drawn per episode (the get-up seed's β̂, Algorithm 1); it
// records the largest |torque| / (2 N·m · s) it was asked for.
class WeakenedPendulum final : public Env {
 public:
  BoxSpace observation_space() const override { return inner_.observation_space(); }
  BoxSpace action_space() const override { return inner_.action_space(); }
  void seed(std::uint64_t seed) override {
    inner_.seed(seed);
    rng_ = base::Rng(seed + 1);
  }
  void reset(std::vector<double>& observation) override {
    scale_ = rng_.uniform(0.3, 0.7);
    scales_seen_.push_back(scale_);
    inner_.reset(observation);
  }
  void step(std::span<const double> action, StepResult& out) override {
    largest_ = std::max(largest_, std::abs(action[0]) / (2.0 * scale_));
    inner_.step(action, out);
  }
  double action_scale() const override { return scale_; }
  double largest_ = 0.0;
  std::vector<double> scales_seen_;

 private:
  Pendulum inner_;
  base::Rng rng_;
  double scale_ = 1.0;
};

TEST(Sac, EachCopyActsWithinItsOwnPerEpisodeScale) {
  Pendulum probe;
  SacConfig c;
  c.warmup_steps = 200;
  c.batch_size = 32;
  Sac sac(c, probe.observation_space(), probe.action_space(), 4);
  sac.set_action_bound(0.9);
  std::vector<std::unique_ptr<Env>> copies;
  std::vector<WeakenedPendulum*> envs;
  for (int i = 0; i < 3; ++i) {
    auto e = std::make_unique<WeakenedPendulum>();
    envs.push_back(e.get());
    copies.push_back(std::move(e));
  }
  VecEnv vec(std::move(copies), 1, 4);
  sac.train_until(vec, 1500);  // warm-up and policy actions, 2+ episodes per copy
  for (const auto* e : envs) {
    EXPECT_GE(e->scales_seen_.size(), 3u);
    EXPECT_LE(e->largest_, 0.9 + 1e-6);  // |a| ≤ β·s in every episode of every copy
    EXPECT_GT(e->largest_, 0.5);
  }
  // evaluate() acts at the environment's scale too.
  WeakenedPendulum eval;
  eval.seed(9);
  evaluate(sac, eval, 2);
  EXPECT_LE(eval.largest_, 0.9 + 1e-6);
  // β·s above 1 is refused with the values.
  sac.set_action_bound(1.0);
  std::vector<double> obs{1, 0, 0}, action(1);
  try {
    sac.act(obs, action, true, 1.2);
    ADD_FAILURE() << "expected a UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("action_scale 1.2"), std::string::npos) << e.what();
  }
}

TEST(Ppo, EachCopyActsWithinItsOwnPerEpisodeScale) {
  Pendulum probe;
  PpoConfig c;
  c.rollout_steps = 250;
  c.sigma_start = c.sigma_end = 2.0;  // wide noise: the clamp to the copy's box is what bounds |a|
  Ppo ppo(c, probe.observation_space(), probe.action_space(), 1);
  std::vector<std::unique_ptr<Env>> copies;
  std::vector<WeakenedPendulum*> envs;
  for (int i = 0; i < 2; ++i) {
    auto e = std::make_unique<WeakenedPendulum>();
    envs.push_back(e.get());
    copies.push_back(std::move(e));
  }
  VecEnv vec(std::move(copies), 1, 1);
  ppo.train_until(vec, 1000);  // 2+ episodes per copy
  for (const auto* e : envs) {
    EXPECT_GE(e->scales_seen_.size(), 2u);
    EXPECT_LE(e->largest_, 1.0 + 1e-6);  // |a| ≤ s·limit in every episode of every copy
    EXPECT_GT(e->largest_, 0.9);         // and the box is the copy's, not a smaller one
  }
  WeakenedPendulum eval;  // the deterministic policy acts at the environment's scale too
  eval.seed(9);
  evaluate(ppo, eval, 2);
  EXPECT_LE(eval.largest_, 1.0 + 1e-6);
  std::vector<double> obs{1, 0, 0}, action(1);
  EXPECT_THROW(ppo.act(obs, action, true, 1.2), base::UserError);  // beyond the action box
}

// A pendulum that once pays an infinite reward: every batch that samples it has an infinite
// critic loss, as a diverging critic would.
class PoisonedPendulum final : public Env {
 public:
  BoxSpace observation_space() const override { return inner_.observation_space(); }
  BoxSpace action_space() const override { return inner_.action_space(); }
  void seed(std::uint64_t seed) override { inner_.seed(seed); }
  void reset(std::vector<double>& observation) override { inner_.reset(observation); }
  void step(std::span<const double> action, StepResult& out) override {
    inner_.step(action, out);
    if (++steps_ == 50) out.reward = std::numeric_limits<double>::infinity();
  }

 private:
  Pendulum inner_;
  int steps_ = 0;
};

TEST(Sac, SkipsUpdatesWithANonFiniteLossAndKeepsItsWeightsFinite) {
  Pendulum probe;
  SacConfig c;
  c.warmup_steps = 40;
  c.batch_size = 16;
  Sac sac(c, probe.observation_space(), probe.action_space(), 3);
  std::vector<std::unique_ptr<Env>> copies;
  copies.push_back(std::make_unique<PoisonedPendulum>());
  VecEnv vec(std::move(copies), 1, 3);
  sac.train_until(vec, 400);
  EXPECT_GT(sac.skipped_updates(), 0);              // batches with the infinite reward
  EXPECT_LT(sac.skipped_updates(), sac.updates());  // the others still learn
  for (float w : sac.parameters()) ASSERT_TRUE(std::isfinite(w));
  std::vector<double> obs{1, 0, 0}, action(1);
  sac.act(obs, action, true, 1.0);
  EXPECT_TRUE(std::isfinite(action[0]));
}

TEST(Sac, FractionalUpdateToDataRatioCountsUpdatesFromEnvironmentSteps) {
  Pendulum probe;
  for (double ratio : {0.25, 1.0 / 3.0, 2.0}) {
    SCOPED_TRACE(ratio);
    SacConfig c;
    c.warmup_steps = 40;
    c.batch_size = 16;
    c.updates_per_step = ratio;
    Sac sac(c, probe.observation_space(), probe.action_space(), 1);
    std::vector<std::unique_ptr<Env>> copies;
    for (int i = 0; i < 4; ++i) copies.push_back(std::make_unique<Pendulum>());
    VecEnv vec(std::move(copies), 1, 1);
    sac.train_until(vec, 200);
    // Updates start with the vector step that reaches 40 env steps: 41 vector steps × 4 copies.
    EXPECT_EQ(sac.updates(), std::int64_t(std::floor(164 * ratio)));
  }
  EXPECT_THROW(Sac(SacConfig::from_json({{"updates_per_step", -0.5}}), probe.observation_space(), probe.action_space(), 1),
               base::UserError);
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

// A pendulum whose every reset offers kStart transitions of its own (as the get-up's fall does),
// each under a zero torque, rewarded −1.
class FallingPendulum final : public Env {
 public:
  static constexpr int kStart = 3;
  BoxSpace observation_space() const override { return inner_.observation_space(); }
  BoxSpace action_space() const override { return inner_.action_space(); }
  void seed(std::uint64_t seed) override { inner_.seed(seed); }
  void reset(std::vector<double>& observation) override {
    inner_.reset(observation);
    starts_.assign(kStart, {.observation = observation, .action = {0.0}, .reward = -1.0, .next_observation = observation});
  }
  void step(std::span<const double> action, StepResult& out) override { inner_.step(action, out); }
  std::span<const Transition> start_transitions() const override { return starts_; }
  std::optional<base::Json> save_state() const override { return inner_.save_state(); }
  void load_state(const base::Json& state) override { inner_.load_state(state); }

 private:
  Pendulum inner_;
  std::vector<Transition> starts_;
};

VecEnv falling_pendulums(std::uint64_t seed, int copies = 1) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < copies; ++i) envs.push_back(std::make_unique<FallingPendulum>());
  return VecEnv(std::move(envs), 1, seed);
}

TEST(VecEnv, GivesEachEpisodesStartTransitionsOnceAndNoneAfterALoad) {
  auto envs = falling_pendulums(1, 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto starts = envs.take_start_transitions(i);
    ASSERT_EQ(starts.size(), std::size_t(FallingPendulum::kStart));
    EXPECT_EQ(starts.back().next_observation, envs.observation(i));
    EXPECT_TRUE(envs.take_start_transitions(i).empty());
  }
  const std::vector<double> actions(2, 0.0);
  for (int t = 0; t < Pendulum::kEpisodeSteps - 1; ++t) envs.step(actions);
  EXPECT_TRUE(envs.take_start_transitions(0).empty());
  envs.step(actions);  // both episodes end and the copies reset
  EXPECT_EQ(envs.take_start_transitions(0).size(), std::size_t(FallingPendulum::kStart));
  auto other = falling_pendulums(2, 2);
  other.load_state(envs.save_state());
  EXPECT_TRUE(other.take_start_transitions(0).empty());
  EXPECT_TRUE(other.take_start_transitions(1).empty());
}

TEST(Sac, StoresEachEpisodesStartTransitionsOnceWithoutCountingThemAsSteps) {
  FallingPendulum probe;
  SacConfig c;
  c.warmup_steps = 64;
  c.batch_size = 32;
  Sac sac(c, probe.observation_space(), probe.action_space(), 3);
  auto envs = falling_pendulums(3, 2);
  // Pendulum episodes are 200 steps: per copy, 300 steps begin 2 episodes (at 0 and 200), 450
  // steps 3.
  sac.train_until(envs, 2 * 300);
  EXPECT_EQ(sac.env_steps(), 600);
  EXPECT_EQ(sac.replay_size(), 600 + 2 * 2 * FallingPendulum::kStart);
  sac.train_until(envs, 2 * 450);
  EXPECT_EQ(sac.env_steps(), 900);
  EXPECT_EQ(sac.replay_size(), 900 + 2 * 3 * FallingPendulum::kStart);
  // The updates owed follow the environment steps alone: as many as without the starts.
  Sac plain(c, probe.observation_space(), probe.action_space(), 3);
  std::vector<std::unique_ptr<Env>> two;
  for (int i = 0; i < 2; ++i) two.push_back(std::make_unique<Pendulum>());
  VecEnv plain_envs(std::move(two), 1, 3);
  plain.train_until(plain_envs, 2 * 450);
  EXPECT_EQ(sac.updates(), plain.updates());
  EXPECT_EQ(plain.replay_size(), 900);
}

TEST(Sac, ResumeWithStartTransitionsEqualsTheUninterruptedRun) {
  FallingPendulum probe;
  SacConfig c;
  c.warmup_steps = 64;
  c.batch_size = 32;
  const auto dir = std::filesystem::temp_directory_path() / ("podium_sac_starts_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Sac whole(c, probe.observation_space(), probe.action_space(), 5);
  auto envs_whole = falling_pendulums(5);
  whole.train_until(envs_whole, 450);

  Sac first(c, probe.observation_space(), probe.action_space(), 5);
  auto envs_first = falling_pendulums(5);
  first.train_until(envs_first, 250);  // an episode began at step 200: its start is stored
  first.save_checkpoint(dir / "sac.pt", envs_first, base::Json::object());
  Sac resumed(c, probe.observation_space(), probe.action_space(), 99);
  auto envs_resumed = falling_pendulums(77);  // fresh episodes, replaced by the checkpoint's
  resumed.load_checkpoint(dir / "sac.pt", envs_resumed);
  resumed.train_until(envs_resumed, 450);
  EXPECT_EQ(resumed.replay_size(), whole.replay_size());
  EXPECT_EQ(resumed.parameters(), whole.parameters());
  std::filesystem::remove_all(dir);
}

// Haarnoja et al. 2018b eq. 18: α rises while the policy's entropy is below the target and falls
// while it is above. One tanh-squashed action has entropy ≤ log 2 (uniform on [−1, 1]), so a
// target of +5 is never reached; −50 is always exceeded (log σ ≥ −5).
TEST(Sac, TemperatureMovesTowardsTheTargetEntropy) {
  Pendulum env;
  for (double target : {5.0, -50.0}) {
    SCOPED_TRACE(target);
    SacConfig c;
    c.warmup_steps = 64;
    c.batch_size = 32;
    c.target_entropy = target;
    c.initial_alpha = 0.1;
    Sac sac(c, env.observation_space(), env.action_space(), 5);
    auto envs = pendulums(5);
    sac.train_until(envs, 200);
    ASSERT_EQ(sac.updates(), 137);
    // Adam moves log α by ≈ alpha_lr per update when the gradient's sign never changes.
    const double moved = std::log(sac.alpha() / c.initial_alpha);
    EXPECT_NEAR(std::abs(moved), 137 * c.alpha_lr, 0.2 * 137 * c.alpha_lr);
    EXPECT_EQ(moved > 0, target > 0);
  }
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
