// Test-only task plugin "test_pendulum" (libpodium_task_test_pendulum.so, built for tests, not a
// shipped task): PPO on learn/'s Pendulum, the smallest real learning trial, for the conformance
// suite and the hand-over and resume acceptance tests of issue 16.
//   param     log10_lr: the policy learning rate, 10^x
//   features  final_return (deterministic evaluation on fixed starts), mean_abs_torque (of it)
//   metrics   eval_return after every update, step 0 = before training (so a warm start's first
//             evaluation can be compared with its source's last); train_return when episodes end
//   artifact  "policy": the TorchScript export
// It checkpoints every `checkpoint_every` updates into its trial folder and a later attempt
// continues from there; with inputs it warm-starts from inputs[0]'s "policy".
#include <cmath>
#include <cstdio>
#include <cstring>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/learn/classic_control.h"
#include "podium/learn/learner.h"
#include "podium/learn/training_checkpoint.h"
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
Evaluation evaluate(learn::Learner& learner, const Settings& s) {
  learn::Pendulum env;
  env.seed(static_cast<std::uint64_t>(s.eval_seed));
  std::vector<double> observation, action(1);
  learn::StepResult step;
  double total = 0.0, torque = 0.0;
  long steps = 0;
  for (int e = 0; e < s.eval_episodes; ++e) {
    env.reset(observation);
    do {
      learner.act(observation, action, true);
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

class PendulumTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    settings_from(config);
    return {{"params", {{{"name", "log10_lr"}, {"low", -4.0}, {"high", -2.0}}}},
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
              {"quick", {{"updates", 150}, {"copies", 8}, {"rollout_steps", 256}, {"minibatch_size", 256},
                         {"hidden", {64, 64}}, {"checkpoint_every", 10}, {"eval_episodes", 5}}},
              {"paper", {{"updates", 150}, {"copies", 8}, {"rollout_steps", 256}, {"minibatch_size", 256},
                         {"hidden", {64, 64}}, {"checkpoint_every", 10}, {"eval_episodes", 20}}}}},
            {"config", accepted_config()},
            {"config_defaults", base::ConfigReader::defaults(accepted_config())}};
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const Settings s = settings_from(request.config);
    const double lr = std::pow(10.0, request.params.at("log10_lr").get<double>());
    std::vector<std::unique_ptr<learn::Env>> copies;
    for (int i = 0; i < s.copies; ++i) copies.push_back(std::make_unique<learn::Pendulum>());
    learn::VecEnv envs(std::move(copies), 1, base::derive_seed(request.seed, 1));
    const std::int64_t total_steps = std::int64_t{s.updates} * s.copies * s.rollout_steps;
    // Pendulum settings of tests/learn/learning_settings.h, σ annealed over the whole trial.
    const Json ppo = {{"hidden", s.hidden},           {"rollout_steps", s.rollout_steps},
                      {"epochs", s.epochs},           {"minibatch_size", s.minibatch_size},
                      {"gamma", 0.95},                {"reward_scale", 0.1},
                      {"policy_lr_start", lr},        {"policy_lr_end", lr},
                      {"sigma_anneal_steps", total_steps}};
    const auto learner = learn::make_learner({{"algorithm", "ppo"}, {"config", ppo}}, envs.observation_space(),
                                             envs.action_space(), base::derive_seed(request.seed, 2));

    // Keeps every metric point with the checkpoint and sends them again on resume (the store
    // drops the repeats); the extra holds the first evaluation and the warm start.
    learn::TrainingCheckpoint checkpoint(
        request.work_dir / "training.ckpt", s.checkpoint_every,
        [&sink](const std::string& name, double step, double value) { sink.metric(name, step, value); });
    Json extra;
    if (auto saved = checkpoint.resume(*learner, envs)) {
      extra = *saved;
      std::fprintf(stderr, "test_pendulum: attempt %d resumes after update %lld\n", request.attempt,
                   static_cast<long long>(checkpoint.updates()));
    } else {
      Json warm_start = nullptr;
      if (!request.inputs.empty()) {
        const auto& input = request.inputs.front();
        const auto policy = input.artifacts.find("policy");
        if (policy == input.artifacts.end())
          throw base::UserError("test_pendulum: input trial " + std::to_string(input.trial_index) + " of stage " +
                                input.stage + " has no \"policy\" artifact");
        learner->warm_start(policy->second);
        warm_start = {{"stage", input.stage}, {"trial_index", input.trial_index}};
      }
      const double first = evaluate(*learner, s).mean_return;
      extra = {{"first_eval_return", first}, {"warm_start", warm_start}};
      checkpoint.metric("eval_return", 0, first);
    }

    Evaluation last = evaluate(*learner, s);
    for (auto update = checkpoint.updates() + 1; update <= s.updates; ++update) {
      if (request.cancel && request.cancel->load())
        throw std::runtime_error("test_pendulum: cancelled before update " + std::to_string(update));
      learn::TrainStats stats;
      learner->train_until(envs, learner->env_steps() + 1, [&](const learn::TrainStats& t) { stats = t; });
      last = evaluate(*learner, s);
      checkpoint.metric("eval_return", static_cast<double>(update), last.mean_return);
      if (stats.episodes > 0) checkpoint.metric("train_return", static_cast<double>(update), stats.mean_return);
      sink.progress(static_cast<double>(update) / s.updates);
      checkpoint.on_update(*learner, envs, extra);
    }

    plugins::RunResult result;
    result.objectives = {last.mean_return};
    result.features = {last.mean_return, last.mean_abs_torque};
    const auto policy = request.work_dir / "policy.pt";
    learner->export_torchscript(policy);
    result.artifacts.push_back({"policy", policy});
    result.info = {{"first_eval_return", extra.at("first_eval_return")},
                   {"warm_start", extra.at("warm_start")},
                   {"parameter_hash", parameter_hash(*learner)}};
    return result;
  }
};

}  // namespace podium::tests::pendulum

PODIUM_EXPORT_TASK(podium::tests::pendulum::PendulumTask, "test_pendulum")
