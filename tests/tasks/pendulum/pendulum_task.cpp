// Test-only task plugin "test_pendulum" (libpodium_task_test_pendulum.so, built for tests, not a
// shipped task): PPO on learn/'s Pendulum on character's training-stage driver, the smallest real
// learning trial, for the conformance suite and the hand-over and resume campaigns
// (tests/orchestrator/handover_campaign_test.cpp).
//   param     log10_lr: the policy learning rate, 10^x
//   features  final_return (deterministic evaluation on fixed starts), mean_abs_torque (of it)
//   metrics   eval_return after every update, step 0 = before training (so a warm start's first
//             evaluation can be compared with its source's last); train_return when episodes end
//   artifact  "policy": the TorchScript export
// It checkpoints every `checkpoint_every` updates into its trial folder and a later attempt
// continues from there; with inputs it warm-starts from inputs[0]'s "policy". Like every
// stage on the driver it sends the time/ series (wall seconds), which the hand-over test compares
// by name and step only.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/character/evaluator.h"
#include "podium/character/training_stage.h"
#include "podium/learn/classic_control.h"
#include "podium/learn/learner.h"
#include "podium/plugins/export.h"

namespace podium::tests::pendulum {

using base::Json;

namespace {

struct Settings {
  int updates = 8;
  int copies = 2;
  int rollout_steps = 64;
  int epochs = 10;
  int minibatch_size = 64;
  std::vector<int> hidden = {16, 16};
  int checkpoint_every = 2;
  int eval_episodes = 1;
  std::int64_t eval_seed = 99;
};

Settings read_settings(base::ConfigReader& r) {
  Settings s;
  s.updates = r.integer<int>("updates", s.updates, {1, 100000}, "PPO iterations");
  s.copies = r.integer<int>("copies", s.copies, {1, 64}, "environment copies");
  s.rollout_steps = r.integer<int>("rollout_steps", s.rollout_steps, {1, 100000}, "steps per copy per iteration");
  s.epochs = r.integer<int>("epochs", s.epochs, {1, 100}, "passes over each batch");
  s.minibatch_size = r.integer<int>("minibatch_size", s.minibatch_size, {1, 100000});
  s.hidden = r.integers<int>("hidden", s.hidden, {1, 4096}, "hidden layer widths");
  s.checkpoint_every = r.integer<int>("checkpoint_every", s.checkpoint_every, {1, 100000}, "updates between checkpoints");
  s.eval_episodes = r.integer<int>("eval_episodes", s.eval_episodes, {1, 1000}, "episodes per evaluation");
  s.eval_seed = r.integer<std::int64_t>("eval_seed", s.eval_seed, {0}, "seed of the evaluation starts (fixed, not the trial's)");
  return s;
}

Settings settings_from(const Json& config) {
  base::ConfigReader reader(config, "", "test_pendulum config");
  Settings s = read_settings(reader);
  reader.finish();
  return s;
}

// What the config accepts (for `podium tasks`), described by the reader that validates it.
Json accepted_config() { return base::ConfigReader::describe(read_settings); }

struct Evaluation {
  double mean_return = 0.0, mean_abs_torque = 0.0;
};

// The deterministic policy on the same starts every time (the generator is seeded per call).
Evaluation evaluate(const character::PolicyFn& policy, const Settings& s) {
  learn::Pendulum env;
  env.seed(static_cast<std::uint64_t>(s.eval_seed));
  std::vector<double> observation, action(1);
  learn::StepResult step;
  double total = 0.0, torque = 0.0;
  long steps = 0;
  for (int e = 0; e < s.eval_episodes; ++e) {
    env.reset(observation);
    do {
      policy(observation, action);
      env.step(action, step);
      total += step.reward;
      torque += std::abs(action[0]);
      ++steps;
      observation = step.observation;
    } while (!step.terminated && !step.truncated);
  }
  return {total / s.eval_episodes, torque / static_cast<double>(steps)};
}

// FNV-1a over the parameters' bytes: equal hashes mean bitwise-equal networks.
std::string parameter_hash(const learn::Learner& learner) {
  std::uint64_t h = 1469598103934665603ull;
  for (float p : learner.parameters()) {
    unsigned char bytes[sizeof p];
    std::memcpy(bytes, &p, sizeof p);
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

}  // namespace

// The trial on the driver: an evaluation after every update (and before the first, test 0), the
// last policy exported; its state the first evaluation and the warm start's source.
class PendulumStage final : public character::TrainingStage {
 public:
  PendulumStage(const Settings& s, double lr, std::uint64_t seed, Json warm_start)
      : s_(s), lr_(lr), seed_(seed), warm_start_(std::move(warm_start)) {}

  void build(const Json&) override {
    std::vector<std::unique_ptr<learn::Env>> copies;
    for (int i = 0; i < s_.copies; ++i) copies.push_back(std::make_unique<learn::Pendulum>());
    envs_ = std::make_unique<learn::VecEnv>(std::move(copies), 1, base::derive_seed(seed_, 1));
  }
  learn::VecEnv& envs() override { return *envs_; }
  // Pendulum settings of tests/learn/learning_settings.h, σ annealed over the whole trial.
  Json learner_spec() const override {
    const Json ppo = {{"hidden", s_.hidden},
                      {"rollout_steps", s_.rollout_steps},
                      {"epochs", s_.epochs},
                      {"minibatch_size", s_.minibatch_size},
                      {"gamma", 0.95},
                      {"reward_scale", 0.1},
                      {"policy_lr_start", lr_},
                      {"policy_lr_end", lr_},
                      {"sigma_anneal_steps", total_steps(s_)}};
    return {{"algorithm", "ppo"}, {"config", ppo}};
  }
  Json state() const override { return {{"first_eval_return", first_eval_return_}, {"warm_start", warm_start_}}; }
  void load_state(const Json& state) override {
    first_eval_return_ = state.at("first_eval_return").get<double>();
    warm_start_ = state.at("warm_start");
  }
  void on_iteration(const character::Iteration& it, learn::Learner&, const character::MetricFn& send) override {
    if (it.training.last.episodes > 0) send("train_return", static_cast<double>(it.index), it.training.last.mean_return);
  }
  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override {
    const double r = evaluate([&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); }, s_).mean_return;
    if (round.test == 0) first_eval_return_ = r;
    send("eval_return", static_cast<double>(round.iteration), r);
    return {{"eval_return", r}};
  }
  void record(const character::Recording& r) override {
    last_ = evaluate([&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); }, s_);
    parameter_hash_ = parameter_hash(r.learner);
  }

  static std::int64_t total_steps(const Settings& s) { return std::int64_t{s.updates} * s.copies * s.rollout_steps; }
  Json info() const {
    return {{"first_eval_return", first_eval_return_}, {"warm_start", warm_start_}, {"parameter_hash", parameter_hash_}};
  }
  const Evaluation& last() const { return last_; }

 private:
  const Settings& s_;
  double lr_;
  std::uint64_t seed_;
  Json warm_start_;
  double first_eval_return_ = 0.0;
  std::unique_ptr<learn::VecEnv> envs_;
  Evaluation last_;
  std::string parameter_hash_;
};

class PendulumTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    settings_from(config);
    Json d = {{"params", {{{"name", "log10_lr"}, {"low", -4.0}, {"high", -2.0}}}},
              {"features",
               {{{"name", "final_return"}, {"low", -2000.0}, {"high", 0.0}, {"metric", "euclidean"}},
                {{"name", "mean_abs_torque"}, {"low", 0.0}, {"high", 2.0}, {"metric", "euclidean"}, {"unit", "N·m"}}}},
              {"metrics",
               {{{"name", "eval_return"}, {"description", "deterministic return on the evaluation starts; step = update"}},
                {{"name", "train_return"}, {"description", "mean return of training episodes finished in the update"}}}},
              {"objectives", {"final_return"}},
              // smoke: seconds per trial; quick and paper: the learn tests' PPO budget (a test task has
              // no paper; paper only evaluates on more starts).
              {"presets",
               {{"smoke", Json::object()},
                {"quick",
                 {{"updates", 150},
                  {"copies", 8},
                  {"rollout_steps", 256},
                  {"minibatch_size", 256},
                  {"hidden", {64, 64}},
                  {"checkpoint_every", 10},
                  {"eval_episodes", 5}}},
                {"paper",
                 {{"updates", 150},
                  {"copies", 8},
                  {"rollout_steps", 256},
                  {"minibatch_size", 256},
                  {"hidden", {64, 64}},
                  {"checkpoint_every", 10},
                  {"eval_episodes", 20}}}}},
              {"config", accepted_config()},
              {"config_defaults", base::ConfigReader::defaults(accepted_config())}};
    for (const Json& m : character::time_metric_entries()) d["metrics"].push_back(m);  // the driver's wall times
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const Settings s = settings_from(request.config);
    const double lr = std::pow(10.0, request.params.at("log10_lr").get<double>());
    std::filesystem::path warm_start;
    Json source = nullptr;
    if (!request.inputs.empty()) {
      const auto& input = request.inputs.front();
      const auto policy = input.artifacts.find("policy");
      if (policy == input.artifacts.end())
        throw base::UserError("test_pendulum: input trial " + std::to_string(input.trial_index) + " of stage " + input.stage +
                              " has no \"policy\" artifact");
      warm_start = policy->second;
      source = {{"stage", input.stage}, {"trial_index", input.trial_index}};
    }
    PendulumStage stage(s, lr, request.seed, source);
    const character::StageOutcome done =
        character::run_training_stage(stage,
                                      {.name = "test_pendulum",
                                       .total_steps = PendulumStage::total_steps(s),
                                       .test_before_training = true,
                                       .checkpoint_every = s.checkpoint_every,
                                       .warm_start = warm_start,
                                       .warm_start_kind = character::StageSettings::WarmStart::policy},
                                      {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});
    plugins::RunResult result;
    result.objectives = {stage.last().mean_return};
    result.features = {stage.last().mean_return, stage.last().mean_abs_torque};
    result.artifacts.push_back({"policy", done.policy});
    result.info = stage.info();
    return result;
  }
};

}  // namespace podium::tests::pendulum

PODIUM_EXPORT_TASK(podium::tests::pendulum::PendulumTask, "test_pendulum")
