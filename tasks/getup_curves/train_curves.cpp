#include "train_curves.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "curve_extraction.h"
#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/character/curriculum.h"
#include "podium/learn/learner.h"

namespace podium::tasks::getup_curves {

using base::Json;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

learn::BoxSpace unit_box(std::size_t n) { return {std::vector<double>(n, -1.0), std::vector<double>(n, 1.0)}; }

Json learner_spec(const TrainSettings& s) { return {{"algorithm", "ppo"}, {"preset", s.ppo_preset}, {"config", s.ppo}}; }

void read_env_settings(base::ConfigReader& r, CurveEnvSettings& e) {
  e.sim_hz = r.number("sim_hz", e.sim_hz, {.min = 0.0, .exclusive_min = true},
                      "simulation rate, Hz, a whole multiple of 30 (the seed's 60 needs pd_solve \"inside\": "
                      "curve_env.h)");
  const double ratio = e.sim_hz / e.control_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9 || ratio < 1.0)
    r.fail("sim_hz", "is not a whole multiple of the control rate " + std::to_string(e.control_hz) + " Hz (§5.6)");
  const std::string pd =
      r.choice("pd_solve", e.control == sim::Control::spd_implicit ? "inside" : "outside", {"outside", "inside"},
               "outside: stable PD by MABA before the contact solve; inside: the PD springs and dampers "
               "implicit in the velocity solve with the contacts (sim's spd_implicit; as the seed's Vortex "
               "motors: humanoid34 stands at 60 Hz with it)");
  e.control = pd == "inside" ? sim::Control::spd_implicit : sim::Control::spd_maba;
  e.stand_s = r.number("stand_s", e.stand_s, {.min = 0.0, .max = 60.0}, "T_stand: an episode lasts T + T_stand (§5.5: 3 s)");
  e.early_termination =
      r.boolean("early_termination", e.early_termination, "§5.3's rule: r_task < 0.1 or the head down for more than 300 ms");
  e.actions = r.choice("actions", e.actions, {"targets", "cvae"},
                       "targets: the policy's filtered action is the PD target pose (§6.4's no-pose-VAE ablation); cvae: "
                       "[z Δq] through the pose C-VAE (§3.4), handed over by one input trial of a pose_cvae stage");
  e.latent_bound = r.number("latent_bound", e.latent_bound, {.min = 0.0, .exclusive_min = true}, "cvae: the latent box ±, σ");
  e.offset_bound = r.number("offset_bound", e.offset_bound, {.min = 0.0}, "cvae: the per-entry offset box ±, rad");
  e.clip_start_noise_rad =
      r.number("clip_start_noise_rad", e.clip_start_noise_rad, {.min = 0.0, .max = 1.0}, "joint noise of a clip start, rad");
  read_terrain_levels(r, e.terrain);
  e.standing_share = r.number("standing_share", e.standing_share, {.min = 0.0, .max = 1.0},
                              "§5.2 (ii): the share of training episodes that start standing, entered at the curve's "
                              "standing part for T_stand; ours: the seed gives none");
  e.standing_tail_s = r.number("standing_tail_s", e.standing_tail_s, {.min = 0.0, .max = 60.0},
                               "§5.2 (ii): on flat a standing start is a frame of a reference clip's last this-many seconds "
                               "(a clip drawn uniformly); 0, off flat or without clips: the model's standing pose");
  e.curve_filter_rad = r.number("curve_filter_deg", e.curve_filter_rad * 180.0 / std::numbers::pi, {.min = 0.0, .max = 180.0},
                                "§5.2: after a drop, a curve whose initial torso angles are farther than this from the "
                                "torso's is replaced by one that is near (30°); 0: no filter") *
                       std::numbers::pi / 180.0;
}

}  // namespace

fs::path shipped_curve_dir() { return fs::path(PODIUM_GETUP_CURVES_DATA_DIR) / "curves"; }

std::vector<fs::path> curve_files(const TrainSettings& s) {
  std::vector<fs::path> files;
  for (const std::string& entry : s.curves) {
    const fs::path p(entry);
    const bool shipped = !p.has_parent_path() && !p.has_extension();
    files.push_back(shipped ? shipped_curve_dir() / (entry + ".json") : p);
  }
  return files;
}

TrainSettings read_train_settings(base::ConfigReader& r) {
  TrainSettings s;
  s.curves = r.strings("curves", s.curves,
                       "curve files (style_curve.h's format) the policy trains on, one drawn per episode: a bare name is a "
                       "shipped curve (tasks/getup_curves/data/curves/<name>.json), anything else a path");
  if (s.curves.empty()) r.fail("curves", "is empty (give at least one curve file)");
  const std::vector<fs::path> files = curve_files(s);
  for (std::size_t k = 0; k < files.size(); ++k) {
    if (!fs::is_regular_file(files[k])) r.fail("curves", k, "is not a curve file (" + files[k].string() + ")");
    try {
      load_style_curve(files[k]);  // a bad curve is named at submit, not when its trial starts
    } catch (const base::UserError& error) {
      r.fail("curves", k, std::string("is not a valid curve: ") + error.what());
    }
  }
  read_env_settings(r, s.env);
  s.ppo_preset = r.choice("ppo_preset", s.ppo_preset, {"quick", "paper"}, "learn's PpoConfig preset under `ppo`");
  s.ppo = r.raw_object("ppo", "PpoConfig fields over the preset (learn/include/podium/learn/ppo.h; §5.6 in presets.json)");
  try {
    learn::make_learner(learner_spec(s), unit_box(1), unit_box(1), 0);
  } catch (const base::UserError& error) {
    r.fail("ppo", error.what());
  }
  s.copies = r.integer<int>("copies", s.copies, {1, 1024}, "env copies stepped together (§5.6: 16 processes)");
  s.threads = r.integer<int>("threads", s.threads, {1, 1024}, "threads stepping the copies");
  if (s.threads > s.copies) r.fail("threads", "is above copies " + std::to_string(s.copies));
  s.total_steps = r.integer<std::int64_t>(
      "total_steps", s.total_steps, {1},
      "control steps at most, every copy's (the seed's 100M simulation steps at 60 Hz are 50M control steps at 30 Hz)");
  s.train_minutes = r.number("train_minutes", s.train_minutes, {.min = 0.0}, "wall-clock budget, minutes; 0: none");
  s.test_every = r.integer<int>("test_every", s.test_every, {1, 1'000'000}, "PPO iterations between tests");
  s.test_starts = r.integer<int>("test_starts", s.test_starts, {1, 10'000}, "test episodes per curve, from fixed starts");
  s.test_seed = r.integer<std::uint64_t>("test_seed", s.test_seed, {}, "the fixed test starts' seed (the same for every trial)");
  s.final_starts = r.integer<int>("final_starts", s.final_starts, {0, 100'000},
                                  "the exported policy's final test: episodes per curve from the fixed starts (the quick bars: "
                                  "20; 0: test_starts)");
  s.record_curves = r.integer<int>("record_curves", s.record_curves, {0, 1000},
                                   "the first curves whose episode with the exported policy is recorded");
  s.checkpoint_every =
      r.integer<int>("checkpoint_every", s.checkpoint_every, {1, 1'000'000}, "PPO iterations between checkpoints");
  s.warm_start = r.existing_file("warm_start", s.warm_start,
                                 "a train trial's training.ckpt to train on from (the same curves and networks; its steps count "
                                 "towards total_steps); empty: from scratch");
  return s;
}

namespace {

// One test episode against its curve, step by step from the reset: the tracking errors over
// [0, T] and the rise.
struct EpisodeTracking {
  double h_error_m = 0.0, angle_error_deg = 0.0;
  int steps = 0;
  std::optional<double> rise_s;
  void add(const CurveGetupEnv& env, double rise_height_m) {
    const double t = env.curve_time_s();
    const StyleFeatures w = env.achieved(), p = env.curve().target(t);
    if (t <= env.curve().duration_s + 1e-9) {
      h_error_m += std::abs(w(0) - p(0));
      angle_error_deg += 0.5 * (std::abs(w(1) - p(1)) + std::abs(w(2) - p(2))) * 180.0 / std::numbers::pi;
      ++steps;
    }
    if (!rise_s && w(0) >= rise_height_m) rise_s = t;
  }
};

CurveFollowing following_of(const std::string& curve, const std::vector<EpisodeTracking>& episodes,
                            const std::vector<char>& successes) {
  CurveFollowing f;
  f.curve = curve;
  double h = 0.0, angle = 0.0, rise = 0.0;
  int tracked = 0;
  for (std::size_t i = 0; i < episodes.size(); ++i) {
    const EpisodeTracking& e = episodes[i];
    if (e.rise_s) rise += *e.rise_s, ++f.risen;
    if (!successes.at(i)) continue;
    ++f.successes;
    if (e.steps > 0) h += e.h_error_m / e.steps, angle += e.angle_error_deg / e.steps, ++tracked;
  }
  f.success_rate = episodes.empty() ? 0.0 : static_cast<double>(f.successes) / static_cast<double>(episodes.size());
  if (tracked > 0) f.h_error_m = h / tracked, f.angle_error_deg = angle / tracked;
  if (f.risen > 0) f.rise_time_s = rise / f.risen;
  return f;
}

Json optional_json(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

}  // namespace

Json CurveFollowing::to_json() const {
  return {{"curve", curve},
          {"success_rate", success_rate},
          {"successes", successes},
          {"h_error_m", optional_json(h_error_m)},
          {"angle_error_deg", optional_json(angle_error_deg)},
          {"rise_time_s", optional_json(rise_time_s)},
          {"risen", risen}};
}

CurveTest test_curves(CurveGetupEnv& env, const character::PolicyFn& policy, int starts, std::uint64_t seed,
                      const CurveStepFn& each_step) {
  env.set_standing_share(0.0);  // the bars start lying
  CurveTest out;
  const std::size_t curves = env.curves().curves.size();
  const double rise_height = 0.5 * standing_neck_height(env.model());
  double task_sum = 0.0;
  std::int64_t task_steps = 0, full_steps = 0;
  std::size_t episodes = 0;
  for (std::size_t k = 0; k < curves; ++k) {
    env.use_curve(static_cast<int>(k));
    character::EvaluationConfig c;
    for (int i = 0; i < starts; ++i) c.start_seeds.push_back(base::derive_seed(seed, static_cast<std::uint64_t>(i)));
    c.success = [](const character::CharacterEnv& e) { return static_cast<const CurveGetupEnv&>(e).succeeded(); };
    c.measures = {{"episode_s", [](const character::CharacterEnv& e) { return e.step_index() * e.control_dt_s(); }}};
    std::vector<EpisodeTracking> tracking(static_cast<std::size_t>(starts));
    c.each_step = [&](std::size_t start, const character::CharacterEnv& e) {
      const auto& ce = static_cast<const CurveGetupEnv&>(e);
      tracking.at(start).add(ce, rise_height);
      if (each_step) each_step(start, ce);
      if (e.step_index() == 0) {  // the reset: no reward yet; the episode's full length
        full_steps += ce.episode_length();
        return;
      }
      task_sum += ce.reward_terms().task, ++task_steps;
    };
    const character::EvaluationReport report = character::evaluate(env, policy, c);
    out.mean_return += report.mean_return * starts;
    out.success_rate += report.success_rate * starts;
    out.mean_episode_s += report.mean("episode_s") * starts;
    out.curve_success.push_back(report.success_rate);
    out.following.push_back(following_of(env.curve().name, tracking, report.successes));
    episodes += static_cast<std::size_t>(starts);
  }
  env.use_curve(-1);
  const auto n = static_cast<double>(episodes);
  out.mean_return /= n, out.success_rate /= n, out.mean_episode_s /= n;
  out.mean_task_reward = task_steps > 0 ? task_sum / static_cast<double>(task_steps) : 0.0;
  // §6.4: cumulative task reward over the steps the episodes would take in full.
  out.average_return_rate = full_steps > 0 ? task_sum / static_cast<double>(full_steps) : 0.0;
  return out;
}

namespace {

// One recorded episode's targets and achieved features at control rate (the dashboard's
// target-vs-achieved plot): heights in m, angles in degrees as in curve files.
struct FeatureSeries {
  std::vector<double> t_s;
  std::array<std::vector<double>, 3> target, achieved;
  void add(const CurveGetupEnv& env) {
    t_s.push_back(env.curve_time_s());
    const StyleFeatures p = env.curve().target(env.curve_time_s()), w = env.achieved();
    for (int f = 0; f < 3; ++f) {
      const double unit = f == 0 ? 1.0 : kDeg;
      target[static_cast<std::size_t>(f)].push_back(p(f) * unit);
      achieved[static_cast<std::size_t>(f)].push_back(w(f) * unit);
    }
  }
  Json to_json() const {
    const auto block = [](const std::array<std::vector<double>, 3>& v) {
      return Json{{"h_m", v[0]}, {"theta_x_deg", v[1]}, {"theta_z_deg", v[2]}};
    };
    return {{"t_s", t_s}, {"target", block(target)}, {"achieved", block(achieved)}};
  }
};

class CurveTrainStage final : public character::TrainingStage {
 public:
  CurveTrainStage(const TrainSettings& settings, std::uint64_t seed)
      : s_(settings),
        seed_(seed),
        curves_(load_curve_set(curve_files(settings), sim::load_shipped_model("humanoid34"))),
        curriculum_(curriculum_config(settings.env.terrain)) {}

  void build(const Json&) override {
    std::vector<std::unique_ptr<learn::Env>> copies;
    copies_.clear();
    for (int i = 0; i < s_.copies; ++i) {
      auto copy = std::make_unique<CurveGetupEnv>(s_.env, curves_);
      copies_.push_back(copy.get());
      copies.push_back(std::move(copy));
    }
    envs_ = std::make_unique<learn::VecEnv>(std::move(copies), s_.threads, base::derive_seed(seed_, 1));
    open_levels();
  }

  // §5.4: every training episode's outcome goes to the curriculum, copy by copy in order; an
  // unlock opens the next region to every copy and is a point of curriculum/open_levels.
  // With §6.4's ablation (terrain_schedule_steps) the step count opens them instead.
  void on_iteration(const character::Iteration& it, learn::Learner&, const character::MetricFn& send) override {
    const TerrainLevels& t = s_.env.terrain;
    for (CurveGetupEnv* copy : copies_)
      for (const auto& [level, success] : copy->take_finished())
        if (t.schedule_steps == 0 && curriculum_.record(level, success)) opened(it.env_steps, send);
    if (t.schedule_steps > 0)
      while (curriculum_.unlocked() < std::min<std::int64_t>(t.levels, 1 + it.env_steps / t.schedule_steps)) {
        curriculum_.open_next();
        opened(it.env_steps, send);
      }
  }
  Json state() const override { return {{"curriculum", curriculum_.state()}}; }
  void load_state(const Json& state) override {
    curriculum_.load_state(state.at("curriculum"));
    open_levels();
  }
  learn::VecEnv& envs() override { return *envs_; }
  Json learner_spec() const override { return getup_curves::learner_spec(s_); }

  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override {
    CurveGetupEnv env(s_.env, curves_);
    const character::PolicyFn policy = [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); };
    env.use_level(0);
    const CurveTest t = test_curves(env, policy, s_.test_starts, s_.test_seed);
    const auto steps = static_cast<double>(round.env_steps);
    // Success per region (§6.3): flat is the test above; each other open region is tested alike.
    send("test/success_rate/" + curriculum_.level_name(0), steps, t.success_rate);
    for (int level = 1; level < curriculum_.unlocked(); ++level) {
      env.use_level(level);
      send("test/success_rate/" + curriculum_.level_name(level), steps,
           test_curves(env, policy, s_.test_starts, s_.test_seed).success_rate);
    }
    send("test/return", steps, t.mean_return);
    send("test/success_rate", steps, t.success_rate);
    send("test/mean_r_task", steps, t.mean_task_reward);
    send("test/average_return_rate", steps, t.average_return_rate);
    send("test/episode_s", steps, t.mean_episode_s);
    if (round.training.episodes > 0) send("train/return", steps, round.training.mean_return());
    char line[200];
    std::snprintf(line, sizeof line, "getup_curves: step %.0f: test return %.2f, success %.2f, r_task %.3f, episode %.2f s",
                  steps, t.mean_return, t.success_rate, t.mean_task_reward, t.mean_episode_s);
    base::log_info(line);
    return {{"return", t.mean_return},
            {"success_rate", t.success_rate},
            {"mean_r_task", t.mean_task_reward},
            {"episode_s", t.mean_episode_s}};
  }

  // The best tested: the higher success rate, then the higher return.
  std::optional<character::ExportReason> export_rule(const character::ExportRecord& tested,
                                                     const character::ExportRecord* exported) override {
    return character::best_by(tested, exported, {{"success_rate"}, {"return"}});
  }

  void record(const character::Recording& r) override;

  TrainOutcome outcome;

 private:
  TrainSettings s_;
  std::uint64_t seed_;
  std::shared_ptr<const CurveSet> curves_;
  std::unique_ptr<learn::VecEnv> envs_;
  std::vector<CurveGetupEnv*> copies_;  // envs_'s, for the curriculum
  character::UnlockCurriculum curriculum_;

  static character::UnlockCurriculum::Config curriculum_config(const TerrainLevels& t) {
    character::UnlockCurriculum::Config c;
    for (int k = 0; k < t.levels; ++k) c.levels.push_back(t.specs.at(static_cast<std::size_t>(k)).name);
    c.successes_to_unlock = t.successes_to_unlock;
    return c;
  }
  void open_levels() {
    for (CurveGetupEnv* copy : copies_) copy->set_open_levels(curriculum_.unlocked());
  }
  void opened(std::int64_t env_steps, const character::MetricFn& send) {
    send("curriculum/open_levels", static_cast<double>(env_steps), curriculum_.unlocked());
    base::log_info("getup_curves: " + curriculum_.level_name(curriculum_.unlocked() - 1) + " opened at step " +
                   std::to_string(env_steps));
    open_levels();
  }
};

// The exported policy from the test starts (its figures at export, sent as evaluation points), and
// one episode per recorded curve written as a motion with its target and achieved features.
void CurveTrainStage::record(const character::Recording& r) {
  const character::PolicyFn policy = [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); };
  CurveGetupEnv env(s_.env, curves_);
  outcome.final = test_curves(env, policy, s_.final_starts > 0 ? s_.final_starts : s_.test_starts, s_.test_seed);  // on flat
  outcome.open_levels = curriculum_.unlocked();
  const auto steps = static_cast<double>(r.exported.env_steps);
  r.send("final/success_rate", steps, outcome.final.success_rate);
  r.send("final/mean_r_task", steps, outcome.final.mean_task_reward);
  Json recorded = Json::array();
  const std::size_t n = std::min(curves_->curves.size(), static_cast<std::size_t>(s_.record_curves));
  for (std::size_t k = 0; k < n; ++k) {
    env.use_curve(static_cast<int>(k));
    std::filesystem::path trajectory;
    recorded.push_back(record_curve_episode(env, policy, base::derive_seed(s_.test_seed, 0),  // the test's first start
                                            r.rollouts / ("curve_" + std::to_string(k)), recorded_trajectory_name(k),
                                            trajectory));
    outcome.trajectories.push_back(trajectory);
    outcome.recorded_curves.push_back(env.curve().name);
  }
  if (n > 0) {
    outcome.curves = r.rollouts / "curves.json";
    base::write_json_file_atomic(outcome.curves, {{"control_hz", s_.env.control_hz}, {"episodes", recorded}});
  }
}

}  // namespace

std::string recorded_trajectory_name(std::size_t k) { return k == 0 ? "trajectory" : "trajectory_" + std::to_string(k); }

Json record_curve_episode(CurveGetupEnv& env, const character::PolicyFn& policy, std::uint64_t seed,
                          const std::filesystem::path& dir, const std::string& trajectory_name,
                          std::filesystem::path& trajectory) {
  env.set_standing_share(0.0);  // a get-up from lying
  FeatureSeries series;
  character::EvaluationConfig c;
  c.start_seeds = {seed};
  c.success = [](const character::CharacterEnv& e) { return static_cast<const CurveGetupEnv&>(e).succeeded(); };
  c.each_step = [&](std::size_t, const character::CharacterEnv& e) { series.add(static_cast<const CurveGetupEnv&>(e)); };
  c.record = {0}, c.record_dir = dir;
  const character::EvaluationReport report = character::evaluate(env, policy, c);
  trajectory = report.trajectories.at(0);
  Json entry = series.to_json();
  entry["curve"] = style_curve_json(env.curve());
  entry["trajectory"] = trajectory_name;
  entry["success"] = report.success_rate > 0.5;
  entry["return"] = report.mean_return;
  return entry;
}

Json TrainOutcome::to_json() const {
  Json following = Json::array();
  for (const CurveFollowing& f : final.following) following.push_back(f.to_json());
  return {{"env_steps", env_steps},
          {"stopped_by", stopped_by},
          {"open_levels", open_levels},
          {"success_rate", final.success_rate},
          {"return", final.mean_return},
          {"mean_r_task", final.mean_task_reward},
          {"average_return_rate", final.average_return_rate},
          {"episode_s", final.mean_episode_s},
          {"curve_success", final.curve_success},
          {"following", following},
          {"recorded_curves", recorded_curves}};
}

TrainOutcome run_curve_training(const TrainSettings& settings, const character::StageRun& run) {
  CurveTrainStage stage(settings, run.seed);
  const character::StageOutcome done = character::run_training_stage(stage,
                                                                     {.name = "getup_curves",
                                                                      .total_steps = settings.total_steps,
                                                                      .steps_per_iteration = 1,
                                                                      .test_every = settings.test_every,
                                                                      .checkpoint_every = settings.checkpoint_every,
                                                                      .train_minutes = settings.train_minutes,
                                                                      .warm_start = settings.warm_start},
                                                                     run);
  TrainOutcome out = std::move(stage.outcome);
  out.policy = done.policy;
  out.env_steps = done.env_steps;
  out.stopped_by = done.stopped_by;
  return out;
}

}  // namespace podium::tasks::getup_curves
