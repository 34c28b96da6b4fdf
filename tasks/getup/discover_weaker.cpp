#include "discover_weaker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "head_watch.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/character/evaluator.h"
#include "podium/learn/learner.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

namespace podium::tasks::getup {

using base::Json;

Settings read_settings(base::ConfigReader& r) {
  Settings s;
  EnvSettings& e = s.env;
  e.variant = r.choice("variant", e.variant, {"none", "casts", "missing_arm"},
                       "§7's character: casts (left elbow, right knee locked) or the left arm removed");
  e.model = r.choice("model", e.model, {"humanoid21_seed", "humanoid21"},
                     "the body: humanoid21_seed, the seed repository's (humanoid_static.xml: armature 0.01, frictionless "
                     "self-contact); humanoid21 without them (the shipped policies' body)");
  e.sim_hz = r.number("sim_hz", e.sim_hz, {.min = 1.0},
                      "π_weak's physics steps per second (the seed repository's humanoid_static.xml: timestep 0.005, 200 Hz; "
                      "App. D's 800 Hz is its Slower's, slow_sim_hz)");
  e.control_hz = r.number("control_hz", e.control_hz, {.min = 1.0}, "policy steps per second (App. D: 40); divides sim_hz");
  const double substeps = e.sim_hz / e.control_hz;
  if (std::abs(substeps - std::round(substeps)) > 1e-9)
    r.fail("control_hz", "does not divide sim_hz " + std::to_string(e.sim_hz));
  e.episode_steps = r.integer<int>("episode_steps", e.episode_steps, {1, 100000}, "control steps per episode (§7: 250)");
  e.fall.drop_height_m = r.number("fall_height_m", e.fall.drop_height_m, {.min = 0.0, .max = 10.0, .exclusive_min = true},
                                  "root height at the ragdoll's release (§7: 1.5)");
  e.fall.control_steps = r.integer<int>("fall_steps", e.fall.control_steps, {0, 10000}, "control steps of the fall (§7: 80)");
  e.fall.action_sigma =
      r.number("fall_sigma", e.fall.action_sigma, {.min = 0.0, .max = 10.0},
               "σ of the fall's random actions, in torque limits (the seed repository's env.py reset: 0, zero torques, its "
               "N(0, 0.1) commented out; §7's text: 0.1)");
  e.fall_transitions = r.boolean("fall_transitions", e.fall_transitions,
                                 "store the fall's control steps in SAC's replay buffer as transitions with their actions "
                                 "and reward, not counted as steps (the seed repository's env.py reset: 80 per episode)");
  e.strength_sigma =
      r.number("strength_sigma", e.strength_sigma, {.min = 0.0, .max = 1.0}, "ε: per-episode β̂ ~ N(β^i, ε) (§5: 0.04)");
  e.passive_joints = r.boolean("passive_joints", e.passive_joints,
                               "the model's passive joint damping and stiffness (humanoid21*: the seed repository's MuJoCo "
                               "humanoid's, always on there)");
  e.min_strength =
      r.number("min_strength", e.min_strength, {.min = 0.0, .max = 1.0, .exclusive_min = true},
               "lower clip of β̂ during the curriculum (the seed repository's power_end, main.py: 0.4); after it, β itself");

  s.algorithm = r.choice("algorithm", s.algorithm, {"sac", "ppo"},
                         "the learner (the seed: SAC; PPO only as a measured choice for a preset)");
  s.sac_preset = r.choice("sac_preset", s.sac_preset, {"quick", "paper"}, "learn's SacConfig preset (paper: Table 1)");
  s.sac = r.raw_object("sac", "SacConfig fields over the preset (learn/include/podium/learn/sac.h)");
  s.ppo = r.raw_object("ppo", "PpoConfig fields over its defaults (learn/include/podium/learn/ppo.h), when algorithm is ppo");
  if (s.sac.contains("log_interval_steps")) r.fail("sac", "log_interval_steps is set by the task (one callback per vector step)");
  Json sac = (s.sac_preset == "paper" ? learn::SacConfig::paper() : learn::SacConfig::quick()).to_json();
  for (const auto& [key, value] : s.sac.items()) sac[key] = value;
  Json ppo = learn::PpoConfig{}.to_json();
  for (const auto& [key, value] : s.ppo.items()) ppo[key] = value;
  try {
    learn::SacConfig::from_json(sac);
  } catch (const base::UserError& error) {
    r.fail("sac", error.what());
  }
  try {
    learn::PpoConfig::from_json(ppo);
  } catch (const base::UserError& error) {
    r.fail("ppo", error.what());
  }

  s.total_steps =
      r.integer<std::int64_t>("total_steps", s.total_steps, {1}, "environment steps at most; a multiple of eval_every");
  s.train_minutes =
      r.number("train_minutes", s.train_minutes, {.min = 0.0},
               "wall-clock minutes of training and tests at most (0: no limit): a preset that fits a slot on any machine; "
               "info.stopped_by says which limit ended the trial");
  s.eval_every = r.integer<std::int64_t>("eval_every", s.eval_every, {1}, "environment steps between tests (App. D: 20000)");
  s.eval_starts = r.integer<int>("eval_starts", s.eval_starts, {1, 1000}, "fixed starts per test (App. D: 10)");
  s.eval_seed = r.integer<std::uint64_t>("eval_seed", s.eval_seed, {}, "picks the fixed starts (not the trial's seed)");
  s.success_height_m = r.number("success_height_m", s.success_height_m, {}, "head top above this at the end: got up (§7: 1.2)");
  // 2 s: no leap of the shipped π_weak kept the head top above 1.2 m for the last 2 s of an episode
  // (RESULTS.md: 1 of 80 for 1.5 s), and π_slow's 100-step standing phase (§6) is longer, so a
  // slowed get-up that stands counts.
  s.stand_steps = r.integer<int>(
      "stand_steps", s.stand_steps, {1, 100000},
      "control steps the head top must stay above success_height_m to the episode's end to count as stood (not a leap's flight)");
  s.curriculum.threshold = r.number("threshold", s.curriculum.threshold, {},
                                    "ω: a minimum test return (over the fixed starts) above it advances (App. D: 60)");
  s.curriculum.factor = r.number("strength_factor", s.curriculum.factor, {.min = 0.0, .max = 0.999, .exclusive_min = true},
                                 "β^{i+1} = factor·β^i (App. D: 0.95)");
  s.budget.factor = r.number("budget_factor", s.budget.factor, {.min = 0.0, .exclusive_min = true},
                             "M_i = clip(factor·N_{i−1}, ...) (§5: 1.5)");
  s.budget.min_steps = r.integer<std::int64_t>("min_steps", s.budget.min_steps, {1}, "N_min (App. D: 3e5)");
  s.budget.max_steps = r.integer<std::int64_t>("max_steps", s.budget.max_steps, {1}, "N_max (App. D: 8e5)");
  if (s.budget.min_steps > s.budget.max_steps) r.fail("min_steps", "is above max_steps " + std::to_string(s.budget.max_steps));
  s.copies = r.integer<int>("copies", s.copies, {1, 64}, "environment copies stepped together");
  s.threads = r.integer<int>("threads", s.threads, {1, 64}, "threads stepping the copies");
  if (s.threads > s.copies) r.fail("threads", "is above copies " + std::to_string(s.copies));
  s.checkpoint_every = r.integer<int>("checkpoint_every", s.checkpoint_every, {1, 1000000}, "tests between training checkpoints");
  s.warm_start = r.existing_file(
      "warm_start", s.warm_start,
      "a Weaker trial's training.ckpt to train on from (same config but for the limits; its steps count towards total_steps)");
  s.hold_strength = r.number("hold_strength", s.hold_strength, {.min = 0.0, .max = 1.0},
                             "> 0: departs from the seed: no curriculum, train (β̂ ~ clip(N(β, ε), β, 1)) and test at this "
                             "strength β, which no test passed (e.g. on from a warm_start); 0: Algorithm 1, the seed's");
  // Tests and checkpoints on episode boundaries: every copy then stands at an episode's start,
  // whose saved state replays bitwise (GetupEnv::save_state), so a resumed trial is exact.
  if (s.eval_every % (std::int64_t{s.copies} * e.episode_steps) != 0)
    r.fail("eval_every",
           "is not a multiple of copies × episode_steps = " + std::to_string(std::int64_t{s.copies} * e.episode_steps));
  if (s.total_steps % s.eval_every != 0) r.fail("total_steps", "is not a multiple of eval_every " + std::to_string(s.eval_every));
  return s;
}

Json learner_spec(const Settings& s) {
  if (s.algorithm == "ppo") return {{"algorithm", "ppo"}, {"preset", "quick"}, {"config", s.ppo}};
  Json config = s.sac;
  config["log_interval_steps"] = s.copies;  // a callback per vector step: cancellation is checked there
  return {{"algorithm", "sac"}, {"preset", s.sac_preset}, {"config", config}};
}

WeakerSchedule::Decision WeakerSchedule::on_test(std::int64_t steps, double test_return) {
  if (ended_) return Decision::carry_on;
  const double tested_at = curriculum_.value();
  if (curriculum_.observe(test_return)) {  // Algorithm 1: R_test > ω
    budget_.on_advance(steps);
    last_passed_ = tested_at;
    return Decision::advance;
  }
  // N_c > M_i: end the curriculum. Discover (β = 1, level 0) has no budget: the seed gives none,
  // and its repository applies M_i only once β < 1.
  if (curriculum_.level() == 0 || !budget_.exhausted(steps)) return Decision::carry_on;
  ended_ = true;
  return Decision::end_curriculum;
}

Json WeakerSchedule::state() const {
  return {{"curriculum", curriculum_.state()}, {"budget", budget_.state()}, {"last_passed", last_passed_}, {"ended", ended_}};
}

void WeakerSchedule::load_state(const Json& state) {
  try {
    curriculum_.load_state(state.at("curriculum"));
    budget_.load_state(state.at("budget"));
    last_passed_ = state.at("last_passed").get<double>();
    ended_ = state.at("ended").get<bool>();
  } catch (const Json::exception& e) {
    throw base::UserError(std::string("getup schedule state: ") + e.what());
  }
}

bool exports_over(const character::Figures& tested, const character::Figures& exported) {
  const double stood = character::figure(tested, "stood_rate"), stood_before = character::figure(exported, "stood_rate");
  if (stood != stood_before) return stood > stood_before;
  return character::figure(tested, "test_return") > character::figure(exported, "test_return");
}

Json TrialOutcome::to_json() const {
  return {{"policy_strength", policy_strength}, {"passed", passed}, {"success_rate", success_rate}, {"test_return", test_return},
          {"final_strength", final_strength},   {"levels", levels}, {"env_steps", env_steps},       {"stopped_by", stopped_by},
          {"features", features.as_vector()}};
}

std::vector<std::uint64_t> test_starts(const Settings& s) {
  std::vector<std::uint64_t> starts;
  for (int k = 0; k < s.eval_starts; ++k) starts.push_back(base::derive_seed(s.eval_seed, static_cast<std::uint64_t>(k)));
  return starts;
}

namespace {

const GetupEnv& as_getup(const character::CharacterEnv& env) { return static_cast<const GetupEnv&>(env); }

character::EvaluationConfig test_config(const Settings& s) {
  character::EvaluationConfig c;
  c.start_seeds = test_starts(s);
  c.measures = {{"head_height_m", [](const character::CharacterEnv& env) { return as_getup(env).weak().head_height_m; }}};
  c.success = [h = s.success_height_m](const character::CharacterEnv& env) { return as_getup(env).weak().head_height_m > h; };
  return c;
}

// Discover and Weaker on the driver: GetupEnv copies at β^i, tests at β^i exactly (App. D), the
// curriculum decided at each test, the export by WeakerSchedule and exports_over.
class WeakerStage final : public character::TrainingStage {
 public:
  WeakerStage(const Settings& s, std::uint64_t seed)
      : s_(s),
        seed_(seed),
        beta_(std::make_shared<double>(s.curriculum.initial)),
        floor_(std::make_shared<double>(s.env.min_strength)),
        schedule_(s.curriculum, s.budget),
        tests_(test_config(s)),
        heads_(tests_.start_seeds.size()),
        on_back_(tests_.start_seeds.size(), 0) {
    // How each fixed start's head top crossed success_height_m after the test's first action: a
    // start that rose and fell again fails bar (a) differently from one that never rose, and drops
    // tell a get-up that stands from a leap loop.
    tests_.each_step = [this](std::size_t start, const character::CharacterEnv& env) {
      if (env.step_index() == 0) on_back_[start] = static_cast<char>(lies_on_back(env));
      if (env.step_index() > 0) heads_[start].observe(env.step_index(), as_getup(env).weak().head_height_m);
    };
  }

  void build(const Json&) override {
    std::vector<std::unique_ptr<learn::Env>> copies;
    for (int i = 0; i < s_.copies; ++i) copies.push_back(std::make_unique<GetupEnv>(s_.env, beta_, true, floor_));
    envs_ = std::make_unique<learn::VecEnv>(std::move(copies), s_.threads, base::derive_seed(seed_, 1));
    test_env_ = std::make_unique<GetupEnv>(s_.env, beta_, false);
  }
  learn::VecEnv& envs() override { return *envs_; }
  Json learner_spec() const override { return getup::learner_spec(s_); }
  Json state() const override { return {{"schedule", schedule_.state()}}; }
  void load_state(const Json& state) override { schedule_.load_state(state.at("schedule")); }
  void begin(bool, learn::Learner& learner) override {
    if (s_.hold_strength > 0.0) schedule_.hold(s_.hold_strength);
    *beta_ = schedule_.strength();
    *floor_ = strength_floor(schedule_, s_.env.min_strength);
    updates_ = sac_updates(learner);
  }

  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override;

  std::optional<character::ExportReason> export_rule(const character::ExportRecord& tested,
                                                     const character::ExportRecord* exported) override {
    using Reason = character::ExportReason;
    if (decision_ == WeakerSchedule::Decision::advance)
      return Reason::passed;                             // π passed at β^i: π_weak until a weaker one passes
    if (exported && exported->reason == Reason::passed)  // after the curriculum's end: tested at the last strength passed
      return ended_before_ && exports_over(tested.figures, exported->figures) ? std::optional(Reason::passed) : std::nullopt;
    // Until a test passes, the best policy is kept (the seed repository's best_model, what its
    // Slower loads as the teacher).
    if (!exported || exports_over(tested.figures, exported->figures)) return Reason::best;
    return std::nullopt;
  }

  // The exported policy at its strength over the fixed starts: its strategy features, and its
  // motion from the first start for the replay.
  void record(const character::Recording& r) override {
    *beta_ = character::figure(r.exported.figures, "strength");
    character::EvaluationConfig record = tests_;
    record.record = {0};
    record.record_dir = r.rollouts;
    std::vector<StrategyRecorder> strategies(
        record.start_seeds.size(), StrategyRecorder(test_env_->model(), test_env_->readings().head_top_m, s_.success_height_m));
    record.each_step = [&](std::size_t start, const character::CharacterEnv& env) {
      if (env.step_index() > 0) strategies[start].observe(env);  // the rise begins after the fall
    };
    const auto recorded = character::evaluate(
        *test_env_, [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a, test_env_->action_scale()); },
        record);
    trajectory_ = recorded.trajectories.at(0);
    std::vector<StrategyFeatures> per_start;
    for (const auto& recorder : strategies) per_start.push_back(recorder.features());
    features_ = mean_features(per_start);
  }

  const WeakerSchedule& schedule() const { return schedule_; }
  const std::filesystem::path& trajectory() const { return trajectory_; }
  const StrategyFeatures& features() const { return features_; }

 private:
  // Only SAC counts its updates; PPO's are its epochs over each rollout.
  static std::int64_t sac_updates(const learn::Learner& learner) {
    const auto* sac = dynamic_cast<const learn::Sac*>(&learner);
    return sac ? sac->updates() : 0;
  }

  const Settings& s_;
  std::uint64_t seed_;
  std::shared_ptr<double> beta_;   // β^i, shared by the copies and the test env
  std::shared_ptr<double> floor_;  // the copies' lower clip of β̂ (strength_floor)
  WeakerSchedule schedule_;
  character::EvaluationConfig tests_;
  std::vector<HeadWatch> heads_;
  std::vector<char> on_back_;
  std::unique_ptr<learn::VecEnv> envs_;
  std::unique_ptr<GetupEnv> test_env_;
  WeakerSchedule::Decision decision_ = WeakerSchedule::Decision::carry_on;
  bool ended_before_ = false;  // the curriculum had ended before the last test
  std::int64_t updates_ = 0;   // SAC's updates at the last test
  std::filesystem::path trajectory_;
  StrategyFeatures features_;
};

character::Figures WeakerStage::test(const character::TestRound& round, learn::Learner& learner,
                                     const character::MetricFn& send) {
  const auto steps = static_cast<double>(round.env_steps);
  const double tested_at = schedule_.strength();
  std::fill(heads_.begin(), heads_.end(), HeadWatch{.height_m = s_.success_height_m});
  const auto result = character::evaluate(
      *test_env_, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true, test_env_->action_scale()); },
      tests_);
  // R_test is the minimum return over the fixed starts (§5: "the accumulated minimum test reward";
  // the seed repository's default): β falls only once every start gets up.
  const double min_return = *std::min_element(result.returns.begin(), result.returns.end());
  const auto* sac = dynamic_cast<const learn::Sac*>(&learner);
  const std::string update_count = sac ? " (" + std::to_string(sac->updates() - updates_) + ")" : "";
  updates_ = sac_updates(learner);
  char line[256];  // the wall times are also metrics (time/)
  std::snprintf(line, sizeof line,
                "getup: step %.0f: test return %.2f (min %.2f) at β %.4f; %.0f env steps/s in rollouts (%.1f s), updates %.1f "
                "s%s, test %.1f s",
                steps, result.mean_return, min_return, tested_at, static_cast<double>(s_.eval_every) / round.training.rollout_s,
                round.training.rollout_s, round.training.update_s, update_count.c_str(), round.seconds());
  base::log_info(line);
  send("test_return", steps, result.mean_return);
  send("test_return_min", steps, min_return);
  send("head_height_m", steps, result.mean("head_height_m"));
  send("success_rate", steps, result.success_rate);
  const HeadSummary rose = summarise_heads(heads_, s_.stand_steps);
  send("risen_rate", steps, static_cast<double>(rose.risen) / static_cast<double>(heads_.size()));
  const double stood_rate = static_cast<double>(rose.stood) / static_cast<double>(heads_.size());
  send("stood_rate", steps, stood_rate);
  // The starts on the back, apart (head_watch.h's BackSummary): a policy may rise from one side only.
  if (const BackSummary back = summarise_back(heads_, on_back_, s_.stand_steps); back.falls > 0) {
    send("risen_on_back_rate", steps, static_cast<double>(back.risen) / back.falls);
    send("stood_on_back_rate", steps, static_cast<double>(back.stood) / back.falls);
  }
  send("head_drops", steps, rose.drops);
  send("head_peak_m", steps, rose.peak_m);
  if (round.training.episodes > 0) send("train_return", steps, round.training.mean_return());
  if (sac) {
    send("sac/alpha", steps, sac->alpha());
    send("sac/skipped_updates", steps, static_cast<double>(sac->skipped_updates()));
  }
  ended_before_ = schedule_.ended();
  decision_ = schedule_.on_test(round.env_steps, min_return);
  *beta_ = schedule_.strength();
  *floor_ = strength_floor(schedule_, s_.env.min_strength);
  send("curriculum/strength", steps, *beta_);
  return {{"strength", tested_at},
          {"test_return", result.mean_return},
          {"test_return_min", min_return},
          {"success_rate", result.success_rate},
          {"stood_rate", stood_rate}};
}

}  // namespace

TrialOutcome run_discover_weaker(const Settings& s, const character::StageRun& run) {
  WeakerStage stage(s, run.seed);
  const character::StageOutcome done = character::run_training_stage(stage,
                                                                     {.name = "getup",
                                                                      .total_steps = s.total_steps,
                                                                      .steps_per_iteration = s.eval_every,
                                                                      .checkpoint_every = s.checkpoint_every,
                                                                      .train_minutes = s.train_minutes,
                                                                      .warm_start = s.warm_start},
                                                                     run);
  if (done.exported.reason == character::ExportReason::last)
    throw std::logic_error("getup: training ended before its first test");
  TrialOutcome out;
  out.policy = done.policy;
  out.trajectory = stage.trajectory();
  out.passed = done.exported.reason == character::ExportReason::passed;
  out.policy_strength = character::figure(done.exported.figures, "strength");
  out.success_rate = character::figure(done.exported.figures, "success_rate");
  out.test_return = character::figure(done.exported.figures, "test_return");
  out.final_strength = stage.schedule().strength();
  out.levels = stage.schedule().level();
  out.env_steps = done.env_steps;
  out.stopped_by = done.stopped_by;
  out.features = stage.features();
  return out;
}

}  // namespace podium::tasks::getup
