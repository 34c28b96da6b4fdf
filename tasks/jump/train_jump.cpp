#include "train_jump.h"

#include <cmath>
#include <cstdio>
#include <regex>
#include <stdexcept>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/learn/ppo.h"
#include "podium/learn/training_checkpoint.h"

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
  s.copies = r.integer<int>("copies", s.copies, {1, 1024}, "JumpEnv copies stepped together (samples per iteration = copies × ppo.rollout_steps)");
  s.threads = r.integer<int>("threads", s.threads, {1, 1024}, "threads stepping the copies");
  if (s.threads > s.copies) r.fail("threads", "is above copies " + std::to_string(s.copies));
  s.total_samples = r.integer<std::int64_t>("total_samples", s.total_samples, {1}, "samples at most (§3.6.2: 12,000 × 4096)");
  s.z_freeze_m = r.number("z_freeze_m", s.z_freeze_m, {.min = 0.0}, "end the trial when z reaches this (§3.6.1: 1 m); 0: never");

  // Table 3.1 for the kind; each key's 0 keeps the table's value (the default is kind-independent).
  s.curriculum = difficulty_curriculum(s.env.kind);
  s.curriculum.initial = s.env.difficulty_m;
  const double step = r.number("z_step_m", 0.0, {.min = 0.0}, "Δz of Table 3.1; 0: the table's (1 cm high jump, 5 cm obstacle)");
  const double threshold = r.number("reward_threshold", 0.0, {.min = 0.0}, "R_T of Table 3.1; 0: the table's (30 high jump, 50 obstacle)");
  const double z_max = r.number("z_max_m", 0.0, {.min = 0.0}, "z_max of Table 3.1; 0: the table's (2 m high jump, 2.5 m obstacle)");
  if (step > 0) s.curriculum.increment = step;
  if (threshold > 0) s.curriculum.threshold = threshold;
  if (z_max > 0) s.curriculum.limit = z_max;
  if (s.curriculum.limit < s.curriculum.initial)
    r.fail("z_max_m", "is below the starting z " + std::to_string(s.curriculum.initial) + " (difficulty_m)");
  s.curriculum_score = r.choice("curriculum_score", s.curriculum_score, {"per_episode", "per_sample"},
                                "an iteration's score for R_T: Σ reward / episodes ended (the authors' runner) or / samples");

  s.eval_every = r.integer<int>("eval_every", s.eval_every, {1, 1000000}, "PPO iterations between tests");
  s.eval.jumps = r.integer<int>("eval_jumps", s.eval.jumps, {1, 10000}, "jumps per test (the first deterministic)");
  s.eval.sigma = r.number("eval_sigma", s.eval.sigma, {.min = 0.0, .max = 1.0}, "action noise of the other test jumps (§3.4.1's final σ)");
  s.eval.seed = r.integer<std::uint64_t>("eval_seed", s.eval.seed, {}, "the test noise's seed (the same for every trial)");
  s.final_jumps = r.integer<int>("final_jumps", s.final_jumps, {1, 10000}, "evaluation jumps at the end, at the starting bar and the final z");
  s.checkpoint_every = r.integer<int>("checkpoint_every", s.checkpoint_every, {1, 1000000}, "PPO iterations between training checkpoints");
  return s;
}

Json learner_spec(const TrainSettings& s) { return {{"algorithm", "ppo"}, {"preset", s.ppo_preset}, {"config", s.ppo}}; }

double iteration_score(const std::string& score, const learn::TrainStats& stats, std::int64_t samples) {
  if (stats.episodes == 0) return 0.0;
  const double sum = stats.mean_return * static_cast<double>(stats.episodes);
  return score == "per_sample" ? sum / static_cast<double>(samples) : sum / static_cast<double>(stats.episodes);
}

JumpTrainer::JumpTrainer(const TrainSettings& settings, std::uint64_t seed, const TrialInputs& inputs, double z_built)
    : s_(settings), seed_(seed), prior_(inputs.prior), known_(inputs.known), curriculum_(settings.curriculum) {
  build_copies(z_built);
  learner_ = learn::make_learner(learner_spec(s_), envs_->observation_space(), envs_->action_space(), base::derive_seed(seed, 2));
  if (!inputs.warm_start.empty()) learner_->warm_start(inputs.warm_start);
}

void JumpTrainer::build_copies(double z) {
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

double JumpTrainer::control_hz() const { return control_hz_for(difficulty_ratio(s_.env.kind, z()), s_.env.sim_hz); }

bool JumpTrainer::frozen() const { return s_.z_freeze_m > 0 && z() >= s_.z_freeze_m - 1e-9; }

bool JumpTrainer::feed(double score) {
  if (!curriculum_.observe(score)) return false;
  bool fits = true;
  for (JumpEnv* env : copies_) fits = env->set_difficulty(z()) && fits;
  if (!fits) build_copies(z()), ++rebuilds_;
  return true;
}

std::unique_ptr<JumpEnv> JumpTrainer::test_env(double z) const {
  JumpSettings settings = s_.env;
  settings.difficulty_m = z;
  auto env = std::make_unique<JumpEnv>(settings, prior_);
  env->set_known_features(known_);
  return env;
}

Json JumpOutcome::to_json() const {
  const auto evaluation = [](const JumpEvaluation& e) {
    return Json{{"success_rate", e.success_rate}, {"deterministic_success", e.deterministic_success},
                {"up_angle_rad", e.up_angle_rad}, {"crossed", e.crossed},
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

namespace {

// One checkpoint file per control rate (the copies it holds step at that rate; sim::World
// restores only into a World of the same rates), with the z its copies were built at beside it.
// The rate only rises with z, so the newest checkpoint is the one of the highest rate.
fs::path checkpoint_file(const fs::path& dir, double hz) { return dir / ("training_" + std::to_string(std::llround(hz)) + "hz.ckpt"); }

struct SavedRun {
  fs::path file;
  double z_built = 0.0;
};

std::optional<SavedRun> newest_checkpoint(const fs::path& dir) {
  static const std::regex name(R"(training_(\d+)hz\.ckpt)");
  std::optional<SavedRun> best;
  long best_hz = -1;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    const long hz = std::stol(m[1]);
    fs::path built = entry.path();
    built.replace_extension(".json");
    if (hz > best_hz && fs::exists(built)) best_hz = hz, best = SavedRun{entry.path(), base::read_json_file(built).at("z_built_m").get<double>()};
  }
  return best;
}

void note_built(const fs::path& file, double z) {
  fs::path built = file;
  built.replace_extension(".json");
  base::write_json_file_atomic(built, {{"z_built_m", z}});
}

void remove_older(const fs::path& dir, const fs::path& keep) {
  static const std::regex name(R"(training_\d+hz\.(ckpt|json))");
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string file = entry.path().filename().string();
    if (std::regex_match(file, name) && entry.path().stem() != keep.stem()) fs::remove(entry.path());
  }
}

}  // namespace

JumpOutcome run_jump_trial(const TrainSettings& s, std::uint64_t seed, const TrialInputs& inputs, const fs::path& work_dir,
                           const std::atomic<bool>* cancel, const Reporter& report) {
  const std::optional<SavedRun> saved = newest_checkpoint(work_dir);
  JumpTrainer trainer(s, seed, inputs, saved ? saved->z_built : s.curriculum.initial);
  const auto hz_of_copies = [&] { return control_hz_for(difficulty_ratio(s.env.kind, trainer.z_built()), s.env.sim_hz); };

  learn::TrainingCheckpoint checkpoint(checkpoint_file(work_dir, hz_of_copies()), s.checkpoint_every,
                                       [&](const std::string& name, double step, double value) { report.metric(name, step, value); });
  const auto send = [&](const std::string& name, double step, double value) { checkpoint.metric(name, step, value); };
  learn::Learner& learner = trainer.learner();
  if (saved) {
    const Json extra = *checkpoint.resume(learner, trainer.envs());
    trainer.load_curriculum(extra.at("curriculum"));
  } else {
    note_built(checkpoint.file(), trainer.z_built());
  }

  const auto progress = [&] {
    double f = static_cast<double>(learner.env_steps()) / static_cast<double>(s.total_samples);
    if (s.z_freeze_m > s.curriculum.initial)
      f = std::max(f, (trainer.z() - s.curriculum.initial) / (s.z_freeze_m - s.curriculum.initial));
    report.progress(std::min(1.0, f));
  };
  progress();
  while (!trainer.frozen() && learner.env_steps() < s.total_samples) {
    learn::TrainStats stats;
    const std::int64_t before = learner.env_steps();
    learner.train_until(trainer.envs(), before + 1, [&](const learn::TrainStats& t) { stats = t; });  // one iteration
    if (cancel && cancel->load()) throw std::runtime_error("jump: cancelled at sample " + std::to_string(learner.env_steps()));
    const auto samples = static_cast<double>(learner.env_steps());
    const double score = iteration_score(s.curriculum_score, stats, learner.env_steps() - before);
    send("train/avg_reward", samples, score);
    send("train/episodes", samples, static_cast<double>(stats.episodes));
    const double built_hz = hz_of_copies();
    if (trainer.feed(score) && std::abs(hz_of_copies() - built_hz) > 1e-9) {
      checkpoint.retarget(checkpoint_file(work_dir, hz_of_copies()));
      note_built(checkpoint.file(), trainer.z_built());
    }
    send("curriculum/z_m", samples, trainer.z());
    send("curriculum/control_hz", samples, hz_of_copies());

    const std::int64_t iteration = checkpoint.updates() + 1;
    if (iteration % s.eval_every == 0) {
      auto env = trainer.test_env(trainer.z());
      const JumpEvaluation e =
          evaluate_jumps(*env, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); }, s.eval);
      send("eval/success_rate", samples, e.success_rate);
      send("eval/return", samples, e.return_mean);
      send("eval/up_angle_rad", samples, e.up_angle_rad);
      send("eval/mean_offset_l1", samples, e.mean_offset_l1);
      char line[200];  // wall times stay out of the metrics (they differ between runs)
      std::snprintf(line, sizeof line, "jump: sample %.0f: z %.2f m at %.0f Hz, score %.3f, test success %.2f, %.1f s rollout, %.1f s update", samples,
                    trainer.z(), hz_of_copies(), score, e.success_rate, stats.rollout_seconds, stats.update_seconds);
      base::log_info(line);
    }
    progress();
    checkpoint.on_update(learner, trainer.envs(), {{"curriculum", trainer.curriculum().state()}});
    if (checkpoint.updates() % s.checkpoint_every == 0) remove_older(work_dir, checkpoint.file());
  }

  JumpOutcome out;
  out.z_reached_m = trainer.z();
  out.levels = trainer.level();
  out.samples = learner.env_steps();
  out.policy = work_dir / "policy.pt";
  learner.export_torchscript(out.policy);
  const auto policy = [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); };
  EvaluationJumps final_jumps = s.eval;
  final_jumps.jumps = s.final_jumps;
  auto start_env = trainer.test_env(s.curriculum.initial);
  out.start_bar = evaluate_jumps(*start_env, policy, final_jumps, work_dir / "rollouts" / "start_bar");
  auto final_env = trainer.test_env(out.z_reached_m);
  out.final_bar = evaluate_jumps(*final_env, policy, final_jumps, work_dir / "rollouts" / "final_bar");
  send("eval/success_rate_start_bar", static_cast<double>(out.samples), out.start_bar.success_rate);
  send("eval/success_rate_final", static_cast<double>(out.samples), out.final_bar.success_rate);
  report.progress(1.0);
  return out;
}

}  // namespace podium::tasks::jump
