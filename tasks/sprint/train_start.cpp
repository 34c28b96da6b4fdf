// The Start stage (sprint seed §3.1) on character's training-stage driver.
#include "train_start.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "crouch_start.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/learn/learner.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::sprint {

using base::Json;
namespace fs = std::filesystem;

StartTrainSettings read_start_train_settings(base::ConfigReader& r) {
  StartTrainSettings s;
  s.track = r.choice("track", s.track, {"smoke", "quick", "paper"},
                     "the sprint preset (tasks/sprint/data/presets.json): track length, rewards, DR ranges, the start block");
  s.sim_hz = r.number("sim_hz", s.sim_hz, {.min = 30.0}, "simulation rate, Hz (a multiple of the 30 Hz control)");
  if (std::abs(s.sim_hz / 30.0 - std::round(s.sim_hz / 30.0)) > 1e-9) r.fail("sim_hz", "is not a multiple of 30 Hz");
  s.ppo_preset = r.choice("ppo_preset", s.ppo_preset, {"quick", "paper"}, "learn's PpoConfig preset");
  s.ppo = r.raw_object("ppo", "PpoConfig fields over the preset (learn/include/podium/learn/ppo.h)");
  try {
    learn::make_learner({{"algorithm", "ppo"}, {"preset", s.ppo_preset}, {"config", s.ppo}}, {{0.0}, {1.0}}, {{-1.0}, {1.0}}, 0);
  } catch (const base::UserError& error) {
    r.fail("ppo", error.what());
  }
  s.copies = r.integer<int>("copies", s.copies, {1, 1024}, "environment copies (samples per iteration = copies × rollout_steps)");
  s.threads = r.integer<int>("threads", s.threads, {1, 1024}, "threads stepping the copies");
  if (s.threads > s.copies) r.fail("threads", "is above copies " + std::to_string(s.copies));
  s.total_samples = r.integer<std::int64_t>("total_samples", s.total_samples, {1}, "samples at most");
  s.eval_every = r.integer<int>("eval_every", s.eval_every, {1, 1'000'000}, "PPO iterations between tests");
  s.eval_episodes = r.integer<int>("eval_episodes", s.eval_episodes, {1, 100'000}, "episodes per test");
  s.final_episodes = r.integer<int>("final_episodes", s.final_episodes, {1, 100'000},
                                    "the exported policy's episodes (its figures and the landing states)");
  s.checkpoint_every = r.integer<int>("checkpoint_every", s.checkpoint_every, {1, 1'000'000}, "iterations between checkpoints");
  s.eval_seed = r.integer<std::uint64_t>("eval_seed", s.eval_seed, {}, "seed of the test episodes (not used in training)");
  s.warm_start = r.existing_file("warm_start", s.warm_start,
                                 "a trial's training.ckpt of the same stage to train on from (the same track, starts and "
                                 "networks; its samples count towards total_samples); empty: from scratch");
  s.clips = read_start_clips(r);
  return s;
}

Json StartEvaluation::to_json() const {
  Json per = Json::object();
  for (const PerReference& r : per_reference)
    per[r.name] = {{"episodes", r.episodes},
                   {"landings", r.landings},
                   {"landing_rate", r.episodes > 0 ? Json(static_cast<double>(r.landings) / r.episodes) : Json(nullptr)}};
  return {{"landing_rate", landing_rate},
          {"tracking_error_rad", tracking_error_rad},
          {"com_speed_ratio", com_speed_ratio},
          {"return", return_mean},
          {"min_reference_landing_rate", min_reference_landing_rate},
          {"per_reference", per},
          {"ends", ends},
          {"landings", landings.size()}};
}

std::string StartEvaluation::ends_text() const {
  std::string out;
  for (const auto& [end, count] : ends) out += (out.empty() ? "" : ", ") + end + " " + std::to_string(count);
  return out;
}

double reference_landing_speed(const character::Clip& clip) {
  if (clip.size() < 2) throw base::UserError("sprint start: a reference needs 2 frames or more");
  const sim::CharacterModel& m = *clip.model;
  Eigen::Vector3d com[2], unused;
  for (int k = 0; k < 2; ++k) {
    sim::CharacterData d(m);
    d.q = clip.poses[clip.size() - 2 + static_cast<std::size_t>(k)];
    sim::forward_kinematics(m, d);
    sim::center_of_mass(m, d, com[k], unused);
  }
  return (com[1].x() - com[0].x()) / (clip.times_s.back() - clip.times_s[clip.size() - 2]);
}

StartEvaluation evaluate_starts(SprintEnv& env, const character::PolicyFn& policy, int episodes, std::uint64_t seed,
                                const fs::path& record_dir) {
  if (episodes < 1) throw base::UserError("sprint start evaluation: episodes " + std::to_string(episodes) + " is not ≥ 1");
  std::vector<double> reference_speed;
  for (const StartReference& r : env.settings().start_references) reference_speed.push_back(reference_landing_speed(*r.clip));
  character::EvaluationConfig c;
  for (int k = 0; k < episodes; ++k) c.start_seeds.push_back(base::derive_seed(seed, static_cast<std::uint64_t>(k)));
  StartEvaluation out;
  for (const StartReference& r : env.settings().start_references) out.per_reference.push_back({r.name, 0, 0});
  double error_sum = 0.0, ratio_sum = 0.0;
  std::int64_t steps = 0;
  c.each_step = [&](std::size_t, const character::CharacterEnv& e) {
    const auto& s = static_cast<const SprintEnv&>(e);
    if (e.step_index() == 0) return;  // the reference's own first frame
    error_sum += s.tracking_errors().pose_rms_rad, ++steps;
    StartEvaluation::PerReference& per = out.per_reference[static_cast<std::size_t>(s.reference_index())];
    if (e.step_index() == 1) ++per.episodes;
    if (s.outcome() != SprintEnv::Outcome::running) ++out.ends[to_string(s.outcome())];
    if (s.outcome() == SprintEnv::Outcome::landed && s.landing_state()) {
      ++per.landings;
      out.landings.push_back(*s.landing_state());
      ratio_sum += e.features().com_vel.x() / reference_speed[static_cast<std::size_t>(s.reference_index())];
    }
  };
  c.success = [](const character::CharacterEnv& e) {
    return static_cast<const SprintEnv&>(e).outcome() == SprintEnv::Outcome::landed;
  };
  if (!record_dir.empty()) c.record = {0}, c.record_dir = record_dir, c.record_min_hz = 60.0;
  const character::EvaluationReport report = character::evaluate(env, policy, c);
  out.landing_rate = report.success_rate;
  out.return_mean = report.mean_return;
  int ended = 0;
  for (const auto& [end, count] : out.ends) ended += count;
  if (ended < episodes) out.ends["time_limit"] = episodes - ended;
  out.tracking_error_rad = steps > 0 ? error_sum / static_cast<double>(steps) : 0.0;
  out.com_speed_ratio = out.landings.empty() ? 0.0 : ratio_sum / static_cast<double>(out.landings.size());
  out.min_reference_landing_rate = 1.0;
  for (const StartEvaluation::PerReference& r : out.per_reference)
    if (r.episodes > 0) out.min_reference_landing_rate = std::min(out.min_reference_landing_rate, 1.0 * r.landings / r.episodes);
  return out;
}

std::vector<StartReference> start_references(const sim::ModelPtr& model, double control_hz, const StartPreset& start,
                                             const std::vector<StartClipSpec>& clips) {
  std::vector<StartReference> refs = crouch_start_references(model, control_hz, start);
  for (const StartClipSpec& c : clips) refs.push_back(user_start_reference(model, control_hz, c));
  return refs;
}

StartStage::StartStage(const StartTrainSettings& settings, std::uint64_t seed) : s_(settings), seed_(seed) {
  const SprintPreset preset = load_sprint_preset(s_.track);
  SprintEnvSettings e;
  references_ = start_references(sim::load_shipped_model(e.model), e.control_hz, preset.start, s_.clips);
}

SprintEnvSettings StartStage::env_settings() const {
  SprintEnvSettings e;
  e.preset = load_sprint_preset(s_.track);
  e.sim_hz = s_.sim_hz;
  e.start_references = references_;
  return e;
}

void StartStage::build(const Json&) {
  const SprintEnvSettings settings = env_settings();
  std::vector<std::unique_ptr<learn::Env>> copies;
  for (int i = 0; i < s_.copies; ++i) copies.push_back(std::make_unique<SprintEnv>(settings));
  envs_ = std::make_unique<learn::VecEnv>(std::move(copies), s_.threads, base::derive_seed(seed_, 1));
}

// DeepMimic's discount (γ = 0.95) for the dense imitation reward unless the config sets one.
Json StartStage::learner_spec() const {
  Json spec = {{"algorithm", "ppo"}, {"preset", s_.ppo_preset}, {"config", s_.ppo}};
  if (!spec["config"].contains("gamma")) spec["config"]["gamma"] = 0.95;
  return spec;
}

character::Figures StartStage::test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) {
  const auto samples = static_cast<double>(round.env_steps);
  SprintEnv env(env_settings());
  const StartEvaluation e = evaluate_starts(
      env, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); }, s_.eval_episodes, s_.eval_seed);
  send("start/return", samples, e.return_mean);
  send("start/landing_rate", samples, e.landing_rate);
  send("start/min_reference_landing_rate", samples, e.min_reference_landing_rate);
  send("start/tracking_error_rad", samples, e.tracking_error_rad);
  send("start/com_speed_ratio", samples, e.com_speed_ratio);
  char line[320];
  std::snprintf(line, sizeof line,
                "start: sample %.0f: return %.2f, landings %.2f, tracking error %.3f rad, COM speed %.2f of the reference's; "
                "ends: %s",
                samples, e.return_mean, e.landing_rate, e.tracking_error_rad, e.com_speed_ratio, e.ends_text().c_str());
  base::log_info(line);
  return {{"min_reference_landing_rate", e.min_reference_landing_rate},
          {"landing_rate", e.landing_rate},
          {"tracking_error_rad", e.tracking_error_rad},
          {"return", e.return_mean}};
}

// Bar (a) asks every reference to land: the lowest per-reference rate first, then all landings,
// then the tracking error.
std::optional<character::ExportReason> StartStage::export_rule(const character::ExportRecord& tested,
                                                               const character::ExportRecord* exported) {
  return character::best_by(tested, exported, {{"min_reference_landing_rate"}, {"landing_rate"}, {"tracking_error_rad", false}});
}

void StartStage::record(const character::Recording& r) {
  SprintEnv env(env_settings());
  final_ = evaluate_starts(
      env, [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); }, s_.final_episodes,
      base::derive_seed(s_.eval_seed, 1), r.rollouts / "start");
  const auto samples = static_cast<double>(r.exported.env_steps);
  r.send("start/final_landing_rate", samples, final_.landing_rate);
  r.send("start/final_tracking_error_rad", samples, final_.tracking_error_rad);
  r.send("start/final_com_speed_ratio", samples, final_.com_speed_ratio);
  trajectory_ = r.rollouts / "start" / "trajectory_0.jsonl";
  landings_ = r.file.parent_path() / "landings.json";
  save_handover_states(landings_.string(), final_.landings);
}

StartOutcome run_start_trial(const StartTrainSettings& settings, const character::StageRun& run) {
  StartStage stage(settings, run.seed);
  const character::StageOutcome done = character::run_training_stage(stage,
                                                                     {.name = "sprint start",
                                                                      .total_steps = settings.total_samples,
                                                                      .steps_per_iteration = 1,
                                                                      .test_every = settings.eval_every,
                                                                      .checkpoint_every = settings.checkpoint_every,
                                                                      .warm_start = settings.warm_start},
                                                                     run);
  StartOutcome out;
  out.final = stage.final_evaluation();
  out.policy = done.policy;
  out.trajectory = stage.trajectory();
  out.landings = stage.landings_file();
  out.samples = done.env_steps;
  return out;
}

}  // namespace podium::tasks::sprint
