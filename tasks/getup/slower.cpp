#include "slower.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/character/evaluator.h"
#include "podium/learn/frozen_policy.h"
#include "podium/learn/learner.h"
#include "podium/learn/training_checkpoint.h"
#include "podium/learn/wall_budget.h"

namespace podium::tasks::getup {

using base::Json;
namespace fs = std::filesystem;

namespace {

bool same_bytes(const fs::path& a, const fs::path& b) {
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  if (!fa || !fb) return false;
  return std::string(std::istreambuf_iterator<char>(fa), {}) == std::string(std::istreambuf_iterator<char>(fb), {});
}

}  // namespace

SlowerConfig read_slower(base::ConfigReader& r) {
  SlowerConfig c;
  SlowerSettings& e = c.env;
  e.kappa_low = r.number("kappa_low", e.kappa_low, {.min = 0.0, .max = 10.0, .exclusive_min = true}, "Slower: κ ~ U(kappa_low, kappa_high) (App. D: 0.2)");
  e.kappa_high = r.number("kappa_high", e.kappa_high, {.min = 0.0, .max = 10.0, .exclusive_min = true}, "Slower: upper κ (App. D: 0.8)");
  if (e.kappa_high < e.kappa_low) r.fail("kappa_high", "is below kappa_low " + std::to_string(e.kappa_low));
  e.rsi_epsilon = r.number("rsi_epsilon", e.rsi_epsilon, {.min = 0.0, .max = 1.0},
                           "Slower: ε-RSI, probability of starting at the fall's end (§6; the seed repository: 0.2)");
  e.residual_bound_rad = r.number("residual_bound_rad", e.residual_bound_rad, {.min = 0.0, .max = 3.2, .exclusive_min = true},
                                  "Slower: residual PD target bound per joint, rad (the seed repository: 1)");
  e.balance_steps = r.integer<int>("balance_steps", e.balance_steps, {0, 100000}, "Slower: standing-phase control steps (§6: 100)");
  e.rise_height_m = r.number("rise_height_m", e.rise_height_m, {.min = 0.0, .exclusive_min = true},
                             "Slower and Evaluate: standing success is the head top above it at the end, m (§6: 1.2)");
  e.reference_end_m = r.number("reference_end_height_m", e.reference_end_m, {.min = 0.0, .exclusive_min = true},
                               "Slower: τ_fast ends at its first frame with the head top above it, m (§6: 1.2; the seed repository: 1.49)");
  e.max_rise_steps = r.integer<int>("max_rise_steps", e.max_rise_steps, {1, 100000}, "Slower: τ_fast's cap in control steps");
  e.rise_attempts = r.integer<int>("rise_attempts", e.rise_attempts, {1, 1000}, "Slower: falls tried in a row for a τ_fast before the trial fails (every episode needs a rise)");
  c.total_steps = r.integer<std::int64_t>("slow_total_steps", c.total_steps, {1}, "Slower: environment steps; a multiple of slow_eval_every");
  c.train_minutes = r.number("slow_train_minutes", c.train_minutes, {.min = 0.0},
                             "Slower: wall-clock minutes of training and tests at most (0: no limit), as Weaker's train_minutes");
  c.eval_every = r.integer<std::int64_t>("slow_eval_every", c.eval_every, {1}, "Slower: environment steps between tests");
  if (c.total_steps % c.eval_every != 0) r.fail("slow_total_steps", "is not a multiple of slow_eval_every " + std::to_string(c.eval_every));
  c.gamma = r.number("slow_gamma", c.gamma, {.min = 0.0, .max = 1.0},
                     "Slower: SAC's discount for π_slow (Table 1: 0.95); `sac.gamma` sets Weaker's");
  c.warm_start = r.string("slow_warm_start", c.warm_start,
                          "Slower: a Slower trial's training.ckpt to train on from (its π_weak must be this trial's); \"\": from scratch");
  if (!c.warm_start.empty() && !fs::is_regular_file(c.warm_start)) r.fail("slow_warm_start", "is not a file: " + c.warm_start);
  c.test_kappa = r.number("slow_test_kappa", c.test_kappa, {.min = 0.0, .max = 10.0, .exclusive_min = true}, "Slower: κ of the tests");
  return c;
}

Json SlowerOutcome::to_json() const {
  return {{"success_rate", success_rate}, {"com_error_m", com_error_m}, {"test_return", test_return}, {"env_steps", env_steps}, {"stopped_by", stopped_by}};
}

Json slower_learner_spec(const Settings& s, const SlowerConfig& c) {
  Json spec = learner_spec(s);
  if (spec["algorithm"] == "sac") spec["config"]["gamma"] = c.gamma;
  return spec;
}

character::EvaluationConfig slower_test(const SlowerSettings& s, std::vector<std::uint64_t> start_seeds) {
  character::EvaluationConfig c;
  c.start_seeds = std::move(start_seeds);
  const auto slower = [](const character::CharacterEnv& env) -> const SlowerEnv& { return static_cast<const SlowerEnv&>(env); };
  c.measures = {{"com_error_m", [slower](const character::CharacterEnv& env) { return slower(env).mean_com_error_m(); }},
                {"tracked_fraction", [slower](const character::CharacterEnv& env) { return slower(env).tracked_fraction(); }},
                {"end_com_gap_m", [slower](const character::CharacterEnv& env) { return slower(env).end_com_gap_m(); }},
                {"final_head_height_m", [slower](const character::CharacterEnv& env) { return slower(env).weak().head_height_m; }}};
  c.success = [slower, h = s.rise_height_m](const character::CharacterEnv& env) {
    return slower(env).standing_phase() && slower(env).weak().head_height_m > h;
  };
  return c;
}


SlowerOutcome run_slower(const Settings& s, const SlowerConfig& c, const WeakPolicy& weak, std::uint64_t seed, const fs::path& work_dir,
                         const std::atomic<bool>* cancel, const Reporter& report) {
  // π_weak is copied into the trial folder: the Evaluate stage regenerates τ_fast from it.
  SlowerOutcome out;
  out.weak_policy = work_dir / "weak_policy.pt";
  if (!fs::exists(out.weak_policy)) fs::copy_file(weak.policy, out.weak_policy);
  const auto teacher = std::make_shared<const learn::FrozenPolicy>(out.weak_policy);

  std::vector<std::unique_ptr<learn::Env>> copies;
  for (int i = 0; i < s.copies; ++i) copies.push_back(std::make_unique<SlowerEnv>(s.env, c.env, teacher, weak.strength, std::nullopt));
  learn::VecEnv envs(std::move(copies), s.threads, base::derive_seed(seed, 1));
  SlowerEnv test_env(s.env, c.env, teacher, weak.strength, c.test_kappa);
  const auto learner = learn::make_learner(slower_learner_spec(s, c), envs.observation_space(), envs.action_space(), base::derive_seed(seed, 2));
  std::vector<std::uint64_t> starts;
  for (int k = 0; k < s.eval_starts; ++k) starts.push_back(base::derive_seed(s.eval_seed, static_cast<std::uint64_t>(k)));
  const character::EvaluationConfig tests = slower_test(c.env, starts);

  learn::TrainingCheckpoint checkpoint(work_dir / "training.ckpt", s.checkpoint_every,
                                       [&](const std::string& name, double step, double value) { report.metric(name, step, value); });
  if (!c.warm_start.empty() && !fs::exists(checkpoint.file())) {
    // The replay buffer and the environments' references come from the source's π_weak: training
    // on from them under another teacher would mix two imitation targets.
    const fs::path source_teacher = fs::path(c.warm_start).parent_path() / "weak_policy.pt";
    if (!same_bytes(source_teacher, out.weak_policy))
      throw base::UserError("getup slower: slow_warm_start " + c.warm_start + " imitated another π_weak (" + source_teacher.string() +
                            " is missing or differs from " + weak.policy.string() + ")");
    checkpoint.start_from(c.warm_start);
  }
  Json extra = {{"last", nullptr}, {"clock", nullptr}};
  if (auto saved = checkpoint.resume(*learner, envs)) extra = *saved;
  // Until this trial's first save, the clock is the source's: it begins anew here.
  if (!c.warm_start.empty() && extra.value("warm_start", std::string()) != c.warm_start) {
    extra["clock"] = nullptr;
    extra["warm_start"] = c.warm_start;
  }
  learn::WallBudget clock(c.train_minutes, extra.value("clock", Json()));
  const auto act = [&](std::span<const double> o, std::span<double> a) { learner->act(o, a, true, 1.0); };
  while (learner->env_steps() < c.total_steps && clock.another_round_fits()) {
    clock.start_round();
    learner->train_until(envs, learner->env_steps() + c.eval_every, [&](const learn::TrainStats& t) {
      if (cancel && cancel->load()) throw std::runtime_error("getup slower: cancelled at environment step " + std::to_string(t.env_steps));
    });
    const auto steps = static_cast<double>(learner->env_steps());
    const auto started = std::chrono::steady_clock::now();
    const auto result = character::evaluate(test_env, act, tests);
    const double com_error_m = result.mean("com_error_m");
    const double tracked = result.mean("tracked_fraction"), end_gap = result.mean("end_com_gap_m");
    char line[280];
    std::snprintf(line, sizeof line,
                  "getup slower: step %.0f: test return %.2f, COM error %.3f m over %.0f%% of the rise, %.3f m below at its end, success %.2f at κ %.2f (test %.1f s)",
                  steps, result.mean_return, com_error_m, 100 * tracked, end_gap, result.success_rate, c.test_kappa,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    base::log_info(line);
    checkpoint.metric("slow/test_return", steps, result.mean_return);
    checkpoint.metric("slow/com_error_m", steps, com_error_m);
    checkpoint.metric("slow/tracked_fraction", steps, tracked);
    checkpoint.metric("slow/end_com_gap_m", steps, end_gap);
    checkpoint.metric("slow/success_rate", steps, result.success_rate);
    extra["last"] = {{"test_return", result.mean_return}, {"com_error_m", com_error_m},
                     {"success_rate", result.success_rate}};
    clock.end_round();
    extra["clock"] = clock.state();
    report.progress(std::max(steps / static_cast<double>(c.total_steps), clock.fraction_used()));
    checkpoint.on_update(*learner, envs, extra);
  }

  out.policy = work_dir / "policy.pt";
  learner->export_torchscript(out.policy);
  const Json& last = extra.at("last");
  out.test_return = last.at("test_return").get<double>();
  out.com_error_m = last.at("com_error_m").get<double>();
  out.success_rate = last.at("success_rate").get<double>();
  out.env_steps = learner->env_steps();
  out.stopped_by = learn::WallBudget::stopped_by(out.env_steps, c.total_steps);
  base::log_info(clock.end_message("getup slower", out.env_steps, c.total_steps));
  // The exported π_slow's motion from the first fixed start at the test κ, for the replay.
  const learn::FrozenPolicy frozen(out.policy);
  character::EvaluationConfig record = tests;
  record.start_seeds.resize(1);
  record.record = {0};
  record.record_dir = work_dir / "rollouts";
  out.trajectory = character::evaluate(test_env, [&](std::span<const double> o, std::span<double> a) { frozen.act(o, a); }, record)
                       .trajectories.at(0);
  return out;
}

}  // namespace podium::tasks::getup
