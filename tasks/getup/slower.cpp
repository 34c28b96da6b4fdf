#include "slower.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/character/evaluator.h"
#include "podium/learn/frozen_policy.h"
#include "podium/learn/learner.h"

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
  e.kappa_low = r.number("kappa_low", e.kappa_low, {.min = 0.0, .max = 10.0, .exclusive_min = true},
                         "Slower: κ ~ U(kappa_low, kappa_high) (App. D: 0.2)");
  e.kappa_high =
      r.number("kappa_high", e.kappa_high, {.min = 0.0, .max = 10.0, .exclusive_min = true}, "Slower: upper κ (App. D: 0.8)");
  if (e.kappa_high < e.kappa_low) r.fail("kappa_high", "is below kappa_low " + std::to_string(e.kappa_low));
  e.rsi_epsilon = r.number("rsi_epsilon", e.rsi_epsilon, {.min = 0.0, .max = 1.0},
                           "Slower: ε-RSI, probability of starting at the fall's end (§6; the seed repository: 0.2)");
  e.residual_bound_rad = r.number("residual_bound_rad", e.residual_bound_rad, {.min = 0.0, .max = 3.2, .exclusive_min = true},
                                  "Slower: residual PD target bound per joint, rad (the seed repository: 1)");
  e.balance_steps = r.integer<int>("balance_steps", e.balance_steps, {0, 100000},
                                   "Slower: standing-phase control steps (the seed repository's env.py _done: 150; §6: 100)");
  e.rise_height_m = r.number("rise_height_m", e.rise_height_m, {.min = 0.0, .exclusive_min = true},
                             "Slower and Evaluate: standing success is the head top above it at the end, m (§6: 1.2)");
  e.reference_end_m = r.number("reference_end_height_m", e.reference_end_m, {.min = 0.0, .exclusive_min = true},
                               "Slower: τ_fast ends reference_end_extra_steps after its first frame with the head origin "
                               "(not its top) above it, m (the seed repository's env.py run_one_episode: 1.4; §6's text: 1.2)");
  e.reference_end_extra_steps =
      r.integer<int>("reference_end_extra_steps", e.reference_end_extra_steps, {0, 1000},
                     "Slower: control steps τ_fast runs on after the head origin passed (env.py end_next_step: 1)");
  e.sim_hz = r.number("slow_sim_hz", e.sim_hz, {.min = 1.0},
                      "Slower: π_slow's physics steps per second (the seed repository's humanoid_high_freq.xml: 800; its "
                      "teacher π_weak runs at sim_hz); control_hz divides it");
  e.standing_pose = r.object(
      "standing_pose",
      [](base::ConfigReader& p) {
        std::vector<std::pair<std::string, double>> pose;
        for (const auto& [joint, angle] : seed_standing_pose())
          pose.emplace_back(joint, p.number(joint, angle, {.min = -3.2, .max = 3.2}, "rad"));
        return pose;
      },
      "Slower: q̂, the standing phase's PD target and R_balance's pose, per joint in rad (the seed repository's env.py "
      "STANDING_POSE)");
  e.standing_com_m = r.number("standing_com_m", e.standing_com_m, {.min = 0.0, .exclusive_min = true},
                              "Slower: h'_com of the standing phase, m (the seed repository's env.py COM_HEIGHT: 0.80326)");
  e.seed_standing = r.choice("standing_target", "seed", {"seed", "model"},
                             "Slower: seed: standing_pose and standing_com_m; model: the model's own standing pose (every "
                             "joint 0) and its observed COM height (what the shipped π_slow trained with)") == "seed";
  e.rise_kd_ratio = r.number("rise_kd_ratio", e.rise_kd_ratio, {.min = 0.0, .exclusive_min = true},
                             "Slower: k_d = k_p / this over the rise (App. D and env.py substep: 10)");
  e.standing_kd_ratio = r.number("standing_kd_ratio", e.standing_kd_ratio, {.min = 0.0, .exclusive_min = true},
                                 "Slower: k_d = k_p / this while standing (the seed repository's env.py substep: 5)");
  e.max_rise_steps = r.integer<int>("max_rise_steps", e.max_rise_steps, {1, 100000}, "Slower: τ_fast's cap in control steps");
  e.rise_attempts =
      r.integer<int>("rise_attempts", e.rise_attempts, {1, 1000},
                     "Slower: falls tried in a row for a τ_fast before the trial fails (every episode needs a rise)");
  c.total_steps =
      r.integer<std::int64_t>("slow_total_steps", c.total_steps, {1}, "Slower: environment steps; a multiple of slow_eval_every");
  c.train_minutes = r.number("slow_train_minutes", c.train_minutes, {.min = 0.0},
                             "Slower: wall-clock minutes of training and tests at most (0: no limit), as Weaker's train_minutes");
  c.eval_every = r.integer<std::int64_t>("slow_eval_every", c.eval_every, {1}, "Slower: environment steps between tests");
  if (c.total_steps % c.eval_every != 0)
    r.fail("slow_total_steps", "is not a multiple of slow_eval_every " + std::to_string(c.eval_every));
  c.gamma = r.number("slow_gamma", c.gamma, {.min = 0.0, .max = 1.0},
                     "Slower: SAC's discount for π_slow (Table 1: 0.95); `sac.gamma` sets Weaker's");
  c.warm_start = r.existing_file(
      "slow_warm_start", c.warm_start,
      "Slower: a Slower trial's training.ckpt to train on from (its π_weak must be this trial's); \"\": from scratch");
  c.test_kappa =
      r.number("slow_test_kappa", c.test_kappa, {.min = 0.0, .max = 10.0, .exclusive_min = true}, "Slower: κ of the tests");
  return c;
}

Json SlowerOutcome::to_json() const {
  return {{"success_rate", success_rate},
          {"com_error_m", com_error_m},
          {"test_return", test_return},
          {"env_steps", env_steps},
          {"stopped_by", stopped_by}};
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
  c.measures = {
      {"com_error_m", [slower](const character::CharacterEnv& env) { return slower(env).mean_com_error_m(); }},
      {"tracked_fraction", [slower](const character::CharacterEnv& env) { return slower(env).tracked_fraction(); }},
      {"end_com_gap_m", [slower](const character::CharacterEnv& env) { return slower(env).end_com_gap_m(); }},
      {"final_head_height_m", [slower](const character::CharacterEnv& env) { return slower(env).weak().head_height_m; }}};
  c.success = [slower, h = s.rise_height_m](const character::CharacterEnv& env) {
    return slower(env).standing_phase() && slower(env).weak().head_height_m > h;
  };
  return c;
}

namespace {

// Slower on the driver: SlowerEnv copies imitating π_weak retimed by κ ~ U(κ_low, κ_high), tested
// at slow_test_kappa; the export is the last π_slow.
class SlowerStage final : public character::TrainingStage {
 public:
  SlowerStage(const Settings& s, const SlowerConfig& c, const WeakPolicy& weak, const fs::path& teacher, std::uint64_t seed)
      : s_(s),
        c_(c),
        strength_(weak.strength),
        teacher_(std::make_shared<const learn::FrozenPolicy>(teacher)),
        seed_(seed),
        tests_(slower_test(c.env, test_starts(s))) {}

  void build(const Json&) override {
    std::vector<std::unique_ptr<learn::Env>> copies;
    for (int i = 0; i < s_.copies; ++i)
      copies.push_back(std::make_unique<SlowerEnv>(s_.env, c_.env, teacher_, strength_, std::nullopt));
    envs_ = std::make_unique<learn::VecEnv>(std::move(copies), s_.threads, base::derive_seed(seed_, 1));
    test_env_ = std::make_unique<SlowerEnv>(s_.env, c_.env, teacher_, strength_, c_.test_kappa);
  }
  learn::VecEnv& envs() override { return *envs_; }
  Json learner_spec() const override { return slower_learner_spec(s_, c_); }

  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override {
    const auto steps = static_cast<double>(round.env_steps);
    const auto result = character::evaluate(
        *test_env_, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true, 1.0); }, tests_);
    const double com_error_m = result.mean("com_error_m");
    const double tracked = result.mean("tracked_fraction"), end_gap = result.mean("end_com_gap_m");
    char line[280];
    std::snprintf(line, sizeof line,
                  "getup slower: step %.0f: test return %.2f, COM error %.3f m over %.0f%% of the rise, %.3f m below at its end, "
                  "success %.2f at κ %.2f (test %.1f s)",
                  steps, result.mean_return, com_error_m, 100 * tracked, end_gap, result.success_rate, c_.test_kappa,
                  round.seconds());
    base::log_info(line);
    send("slow/test_return", steps, result.mean_return);
    send("slow/com_error_m", steps, com_error_m);
    send("slow/tracked_fraction", steps, tracked);
    send("slow/end_com_gap_m", steps, end_gap);
    send("slow/success_rate", steps, result.success_rate);
    return {{"test_return", result.mean_return}, {"com_error_m", com_error_m}, {"success_rate", result.success_rate}};
  }

  // The exported π_slow's motion from the first fixed start at the test κ, for the replay.
  void record(const character::Recording& r) override {
    character::EvaluationConfig record = tests_;
    record.start_seeds.resize(1);
    record.record = {0};
    record.record_dir = r.rollouts;
    trajectory_ = character::evaluate(
                      *test_env_, [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); }, record)
                      .trajectories.at(0);
  }

  const fs::path& trajectory() const { return trajectory_; }

 private:
  const Settings& s_;
  const SlowerConfig& c_;
  double strength_;  // β π_weak passed at
  std::shared_ptr<const learn::FrozenPolicy> teacher_;
  std::uint64_t seed_;
  character::EvaluationConfig tests_;
  std::unique_ptr<learn::VecEnv> envs_;
  std::unique_ptr<SlowerEnv> test_env_;
  fs::path trajectory_;
};

}  // namespace

SlowerOutcome run_slower(const Settings& s, const SlowerConfig& c, const WeakPolicy& weak, const character::StageRun& run) {
  // π_weak is copied into the trial folder: the Evaluate stage regenerates τ_fast from it.
  SlowerOutcome out;
  out.weak_policy = run.work_dir / "weak_policy.pt";
  if (!fs::exists(out.weak_policy)) fs::copy_file(weak.policy, out.weak_policy);
  if (!c.warm_start.empty() && !fs::exists(run.work_dir / "training.ckpt")) {
    // The replay buffer and the environments' references come from the source's π_weak: training
    // on from them under another teacher would mix two imitation targets.
    const fs::path source_teacher = fs::path(c.warm_start).parent_path() / "weak_policy.pt";
    if (!same_bytes(source_teacher, out.weak_policy))
      throw base::UserError("getup slower: slow_warm_start " + c.warm_start + " imitated another π_weak (" +
                            source_teacher.string() + " is missing or differs from " + weak.policy.string() + ")");
  }
  SlowerStage stage(s, c, weak, out.weak_policy, run.seed);
  const character::StageOutcome done = character::run_training_stage(stage,
                                                                     {.name = "getup slower",
                                                                      .total_steps = c.total_steps,
                                                                      .steps_per_iteration = c.eval_every,
                                                                      .checkpoint_every = s.checkpoint_every,
                                                                      .train_minutes = c.train_minutes,
                                                                      .warm_start = c.warm_start},
                                                                     run);
  out.policy = done.policy;
  out.trajectory = stage.trajectory();
  out.test_return = character::figure(done.exported.figures, "test_return");
  out.com_error_m = character::figure(done.exported.figures, "com_error_m");
  out.success_rate = character::figure(done.exported.figures, "success_rate");
  out.env_steps = done.env_steps;
  out.stopped_by = done.stopped_by;
  return out;
}

}  // namespace podium::tasks::getup
