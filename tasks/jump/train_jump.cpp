#include "train_jump.h"

#include <cmath>
#include <cstdio>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/learn/ppo.h"

namespace podium::tasks::jump {

using base::Json;
namespace fs = std::filesystem;

TrainSettings read_train_settings(base::ConfigReader& r) {
  TrainSettings s;
  s.env = read_jump_settings(r);
  try {
    control_hz_for(0.0, s.env.sim_hz);
  } catch (const base::UserError& error) {
    r.fail("sim_hz", "is not a whole number of Hz (a control step is a whole number of simulation steps)");
  }
  s.ppo_preset = r.choice("ppo_preset", s.ppo_preset, {"quick", "paper"}, "learn's PpoConfig preset (paper: §3.6.2)");
  s.ppo = r.raw_object("ppo", "PpoConfig fields over the preset (learn/include/podium/learn/ppo.h)");
  try {
    learn::make_learner(learner_spec(s), {{0.0}, {1.0}}, {{-1.0}, {1.0}}, 0);
  } catch (const base::UserError& error) {
    r.fail("ppo", error.what());
  }
  s.copies = r.integer<int>("copies", s.copies, {1, 1024},
                            "JumpEnv copies stepped together (samples per iteration = copies × ppo.rollout_steps)");
  s.threads = r.integer<int>("threads", s.threads, {1, 1024}, "threads stepping the copies");
  if (s.threads > s.copies) r.fail("threads", "is above copies " + std::to_string(s.copies));
  s.total_samples = r.integer<std::int64_t>("total_samples", s.total_samples, {1}, "samples at most (§3.6.2: 12,000 × 4096)");
  s.z_freeze_m = r.number("z_freeze_m", s.z_freeze_m, {.min = 0.0}, "end the trial when z reaches this (§3.6.1: 1 m); 0: never");

  // Table 3.1 for the kind; each key's 0 keeps the table's value (the default is kind-independent).
  s.curriculum = difficulty_curriculum(s.env.kind);
  s.curriculum.initial = s.env.difficulty_m;
  const double step = r.number("z_step_m", 0.0, {.min = 0.0}, "Δz of Table 3.1; 0: the table's (1 cm high jump, 5 cm obstacle)");
  const double threshold =
      r.number("reward_threshold", 0.0, {.min = 0.0}, "R_T of Table 3.1; 0: the table's (30 high jump, 50 obstacle)");
  const double z_max =
      r.number("z_max_m", 0.0, {.min = 0.0}, "z_max of Table 3.1; 0: the table's (2 m high jump, 2.5 m obstacle)");
  if (step > 0) s.curriculum.increment = step;
  if (threshold > 0) s.curriculum.threshold = threshold;
  if (z_max > 0) s.curriculum.limit = z_max;
  if (s.curriculum.limit < s.curriculum.initial)
    r.fail("z_max_m", "is below the starting z " + std::to_string(s.curriculum.initial) + " (difficulty_m)");
  s.curriculum_score = r.choice("curriculum_score", s.curriculum_score, {"per_episode", "per_sample"},
                                "an iteration's score for R_T: Σ reward / episodes ended (the authors' runner) or / samples");

  s.eval_every = r.integer<int>("eval_every", s.eval_every, {1, 1000000}, "PPO iterations between tests");
  s.eval.jumps = r.integer<int>("eval_jumps", s.eval.jumps, {1, 10000}, "jumps per test (the first deterministic)");
  s.eval.sigma =
      r.number("eval_sigma", s.eval.sigma, {.min = 0.0, .max = 1.0}, "action noise of the other test jumps (§3.4.1's final σ)");
  s.eval.seed = r.integer<std::uint64_t>("eval_seed", s.eval.seed, {}, "the test noise's seed (the same for every trial)");
  s.final_jumps = r.integer<int>("final_jumps", s.final_jumps, {1, 10000},
                                 "evaluation jumps at the end, at the starting bar and the final z");
  s.checkpoint_every =
      r.integer<int>("checkpoint_every", s.checkpoint_every, {1, 1000000}, "PPO iterations between training checkpoints");
  return s;
}

Json learner_spec(const TrainSettings& s) { return {{"algorithm", "ppo"}, {"preset", s.ppo_preset}, {"config", s.ppo}}; }

double iteration_score(const std::string& score, const learn::TrainStats& stats, std::int64_t samples) {
  if (stats.episodes == 0) return 0.0;
  const double sum = stats.mean_return * static_cast<double>(stats.episodes);
  return score == "per_sample" ? sum / static_cast<double>(samples) : sum / static_cast<double>(stats.episodes);
}

JumpStage::JumpStage(const TrainSettings& settings, std::uint64_t seed, const TrialInputs& inputs)
    : s_(settings), seed_(seed), prior_(inputs.prior), known_(inputs.known), curriculum_(settings.curriculum) {}

void JumpStage::build(const Json& built) {
  build_copies(built.is_null() ? s_.curriculum.initial : built.at("z_built_m").get<double>());
}

void JumpStage::build_copies(double z) {
  JumpSettings settings = s_.env;
  settings.difficulty_m = z;
  std::vector<std::unique_ptr<learn::Env>> copies;
  copies_.clear();
  for (int i = 0; i < s_.copies; ++i) {
    auto env = std::make_unique<JumpEnv>(settings, prior_);
    env->set_known_features(known_);
    copies_.push_back(env.get());
    copies.push_back(std::move(env));
  }
  // Seeded by the rate, so a resumed trial builds the copies it checkpointed.
  const double hz = control_hz_for(difficulty_ratio(s_.env.kind, z), s_.env.sim_hz);
  envs_ = std::make_unique<learn::VecEnv>(std::move(copies), s_.threads,
                                          base::derive_seed(seed_, 1, static_cast<std::uint64_t>(std::llround(hz))));
  z_built_ = z;
}

double JumpStage::control_hz() const { return control_hz_for(difficulty_ratio(s_.env.kind, z()), s_.env.sim_hz); }

double JumpStage::hz_of_copies() const { return control_hz_for(difficulty_ratio(s_.env.kind, z_built_), s_.env.sim_hz); }

// One checkpoint file per control rate: the copies it holds step at that rate, and sim::World
// restores only into a World of the same rates.
std::string JumpStage::checkpoint_tag() const { return std::to_string(std::llround(hz_of_copies())) + "hz"; }

bool JumpStage::frozen() const { return s_.z_freeze_m > 0 && z() >= s_.z_freeze_m - 1e-9; }

double JumpStage::progress() const {
  if (s_.z_freeze_m <= s_.curriculum.initial) return 0.0;
  return (z() - s_.curriculum.initial) / (s_.z_freeze_m - s_.curriculum.initial);
}

bool JumpStage::feed(double score) {
  if (!curriculum_.observe(score)) return false;
  bool fits = true;
  for (JumpEnv* env : copies_) fits = env->set_difficulty(z()) && fits;
  if (!fits) build_copies(z()), ++rebuilds_;
  return true;
}

std::unique_ptr<JumpEnv> JumpStage::test_env(double z) const {
  JumpSettings settings = s_.env;
  settings.difficulty_m = z;
  auto env = std::make_unique<JumpEnv>(settings, prior_);
  env->set_known_features(known_);
  return env;
}

void JumpStage::on_iteration(const character::Iteration& it, learn::Learner&, const character::MetricFn& send) {
  const auto samples = static_cast<double>(it.env_steps);
  last_stats_ = it.training.last;
  score_ = iteration_score(s_.curriculum_score, last_stats_, it.env_steps - it.env_steps_before);
  send("train/avg_reward", samples, score_);
  send("train/episodes", samples, static_cast<double>(last_stats_.episodes));
  feed(score_);
  send("curriculum/z_m", samples, z());
  send("curriculum/control_hz", samples, hz_of_copies());
}

character::Figures JumpStage::test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) {
  const auto samples = static_cast<double>(round.env_steps);
  auto env = test_env(z());
  const JumpEvaluation e = evaluate_jumps(
      *env, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); }, s_.eval);
  send("eval/success_rate", samples, e.success_rate);
  send("eval/return", samples, e.return_mean);
  send("eval/up_angle_rad", samples, e.up_angle_rad);
  send("eval/mean_offset_l1", samples, e.mean_offset_l1);
  char line[200];  // the wall times are also metrics (time/)
  std::snprintf(line, sizeof line,
                "jump: sample %.0f: z %.2f m at %.0f Hz, score %.3f, test success %.2f, %.1f s rollout, %.1f s update", samples,
                z(), hz_of_copies(), score_, e.success_rate, last_stats_.rollout_seconds, last_stats_.update_seconds);
  base::log_info(line);
  return {{"success_rate", e.success_rate}, {"return", e.return_mean}, {"z_m", z()}};
}

void JumpStage::record(const character::Recording& r) {
  const auto policy = [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); };
  EvaluationJumps final_jumps = s_.eval;
  final_jumps.jumps = s_.final_jumps;
  auto start_env = test_env(s_.curriculum.initial);
  start_bar_ = evaluate_jumps(*start_env, policy, final_jumps, r.rollouts / "start_bar");
  auto final_env = test_env(z());
  final_bar_ = evaluate_jumps(*final_env, policy, final_jumps, r.rollouts / "final_bar");
  const auto samples = static_cast<double>(r.exported.env_steps);
  r.send("eval/success_rate_start_bar", samples, start_bar_.success_rate);
  r.send("eval/success_rate_final", samples, final_bar_.success_rate);
}

Json JumpOutcome::to_json() const {
  const auto evaluation = [](const JumpEvaluation& e) {
    return Json{{"success_rate", e.success_rate},
                {"deterministic_success", e.deterministic_success},
                {"up_angle_rad", e.up_angle_rad},
                {"crossed", e.crossed},
                {"bar_frame_rotation", {e.bar_rotation(0), e.bar_rotation(1), e.bar_rotation(2)}},
                {"mean_offset_l1", e.mean_offset_l1}};
  };
  const JumpEvaluation& s = shown();
  return {{"z_reached_m", z_reached_m},
          {"levels", levels},
          {"samples", samples},
          {"start_bar", evaluation(start_bar)},
          {"final_bar", evaluation(final_bar)},
          {"shown", &s == &final_bar ? "final_bar" : "start_bar"},
          {"bar_frame_rotation", {s.bar_rotation(0), s.bar_rotation(1), s.bar_rotation(2)}}};
}

JumpOutcome run_jump_trial(const TrainSettings& s, const TrialInputs& inputs, const character::StageRun& run) {
  JumpStage stage(s, run.seed, inputs);
  const character::StageOutcome done =
      character::run_training_stage(stage,
                                    {.name = "jump",
                                     .total_steps = s.total_samples,
                                     .steps_per_iteration = 1,
                                     .test_every = s.eval_every,
                                     .checkpoint_every = s.checkpoint_every,
                                     .warm_start = inputs.warm_start,
                                     .warm_start_kind = character::StageSettings::WarmStart::policy},
                                    run);
  JumpOutcome out;
  out.z_reached_m = stage.z();
  out.levels = stage.level();
  out.samples = done.env_steps;
  out.policy = done.policy;
  out.start_bar = stage.start_bar();
  out.final_bar = stage.final_bar();
  return out;
}

}  // namespace podium::tasks::jump
