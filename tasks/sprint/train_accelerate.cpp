// The Acceleration + Top Speed stage (sprint seed §3.2) on character's training-stage driver.
#include "train_accelerate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "crouch_start.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/character/evaluator.h"
#include "run_metrics.h"

namespace podium::tasks::sprint {

using base::Json;
namespace fs = std::filesystem;

void read_accelerate_settings(base::ConfigReader& r, AccelerateSettings& s) {
  s.handover_before_line_m =
      r.number("handover_before_line_m", s.handover_before_line_m, {0.0, 1000.0},
               "accelerate: the dip stage's snapshots are taken when the root first passes this far before the line, m");
  s.rise_lean_deg =
      r.number("rise_lean_deg", s.rise_lean_deg, {0.0, 90.0, true},
               "accelerate: the rise distance is where the trunk's lean from vertical drops below this for good, degrees");
  s.primitive_weight =
      r.number("primitive_weight", s.primitive_weight, {0.0, 1e3},
               "accelerate: w_primitive of r_primitive (§3.2, the sport primitive), given per completed stride; 0: off");
  PrimitiveSettings& p = s.primitive;
  p.clips = r.objects(
      "primitive_clips",
      [](base::ConfigReader& c) { return c.file("clip", base::required, "a DeepMimic-format run in humanoid34's joint layout"); },
      "accelerate: the sport primitive's reference runs (§3.2; e.g. ../shared/data's 3-4 m/s runs), needed when "
      "primitive_weight is not 0");
  p.frames = r.integer<int>("primitive_frames", p.frames, {2, 256}, "accelerate: K, frames per stride");
  p.latent = r.integer<int>("primitive_latent", p.latent, {1, 64}, "accelerate: Φ1's latent size");
  p.epochs = r.integer<int>("primitive_epochs", p.epochs, {1, 100'000}, "accelerate: Φ1's pretraining epochs");
  p.beta = r.number("primitive_beta", p.beta, {0.0, 1e3}, "accelerate: Φ1's KL weight (β-VAE)");
  p.reference_strides =
      r.integer<int>("primitive_reference_strides", p.reference_strides, {2, 100'000}, "accelerate: n, the reference's strides");
  p.k = r.number("primitive_k", p.k, {0.0, 1e6}, "accelerate: k of r_primitive = exp(−k·KL); 0: ln 2 / the held-out median KL");
  p.online =
      r.boolean("primitive_online", p.online, "accelerate: Φ2 trained online on the character's strides (false: Φ1's ablation)");
  p.online_epochs =
      r.integer<int>("primitive_online_epochs", p.online_epochs, {1, 1000}, "accelerate: Φ2's epochs per iteration");
  p.online_buffer =
      r.integer<int>("primitive_online_buffer", p.online_buffer, {1, 1'000'000}, "accelerate: Φ2's latest strides kept");
}

std::vector<Json> fallback_starts(const std::string& track, double sim_hz, std::optional<double> root_x_m) {
  const SprintPreset preset = load_sprint_preset(track);
  SprintEnvSettings e;
  e.preset = preset;
  e.sim_hz = sim_hz;
  std::vector<Json> starts;
  for (const StartReference& r : crouch_start_references(sim::load_shipped_model(e.model), e.control_hz, preset.start)) {
    SprintEnvSettings at = e;
    at.start_q = r.clip->poses.back();
    if (root_x_m) at.start_q(0) = *root_x_m;
    at.start_qd = r.clip->velocities().back();
    SprintEnv env(at);
    std::vector<double> observation;
    env.reset(observation);
    starts.push_back({{"world", env.handover_state().at("world")}});  // no draw: each episode draws its own
  }
  return starts;
}

Json RunEvaluation::to_json() const {
  return {{"finish_rate", finish_rate},       {"distance_m", distance_m},   {"first_speed_mps", first_speed_mps},
          {"last_speed_mps", last_speed_mps}, {"segment_m", segment_m},     {"rise_distance_m", rise_distance_m},
          {"rise_rate", rise_rate},           {"flight_rate", flight_rate}, {"return", return_mean},
          {"handovers", handovers.size()}};
}

namespace {

// One episode's samples, one per control step from the start state.
struct Trace {
  std::vector<double> t_s, x_m, lean_rad;
  std::vector<FootContacts> contacts;
  bool finished = false, snapped = false;
};

// The trunk's lean from vertical: the angle between the torso body's up axis and +z.
double trunk_lean(const SprintEnv& env) {
  const Eigen::Matrix3d& R = env.world().data().links[static_cast<std::size_t>(env.model().torso_body())].R;
  return std::acos(std::clamp(R(2, 2), -1.0, 1.0));
}

double mean_of(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

}  // namespace

RunEvaluation evaluate_runs(SprintEnv& env, const character::PolicyFn& policy, int episodes, std::uint64_t seed,
                            const AccelerateSettings& settings, const fs::path& record_dir) {
  if (episodes < 1) throw base::UserError("sprint accelerate evaluation: episodes " + std::to_string(episodes) + " is not ≥ 1");
  const double length = env.settings().preset.track.length_m, snapshot_x = length - settings.handover_before_line_m;
  character::EvaluationConfig c;
  for (int k = 0; k < episodes; ++k) c.start_seeds.push_back(base::derive_seed(seed, static_cast<std::uint64_t>(k)));
  std::vector<Trace> traces(static_cast<std::size_t>(episodes));
  RunEvaluation out;
  c.each_step = [&](std::size_t i, const character::CharacterEnv& e) {
    const auto& s = static_cast<const SprintEnv&>(e);
    Trace& tr = traces[i];
    const sim::Observation& f = s.features();
    const double x = s.world().data().q(0);
    tr.t_s.push_back(static_cast<double>(s.step_index()) / s.settings().control_hz);
    tr.x_m.push_back(x);
    tr.lean_rad.push_back(trunk_lean(s));
    tr.contacts.push_back({f.touches(s.bodies().left_foot, sim::Contact::Partner::ground),
                           f.touches(s.bodies().right_foot, sim::Contact::Partner::ground)});
    if (!tr.snapped && x >= snapshot_x && s.outcome() == SprintEnv::Outcome::running)
      tr.snapped = true, out.handovers.push_back(s.handover_state());  // §3.3's start, with its draw
  };
  std::size_t ended = 0;
  c.success = [&](const character::CharacterEnv& e) {
    const bool finished = static_cast<const SprintEnv&>(e).outcome() == SprintEnv::Outcome::finished;
    traces[ended++].finished = finished;
    return finished;
  };
  if (!record_dir.empty()) c.record = {0}, c.record_dir = record_dir, c.record_min_hz = 60.0;
  const character::EvaluationReport report = character::evaluate(env, policy, c);
  out.finish_rate = report.success_rate;
  out.return_mean = report.mean_return;
  out.segment_m = std::min(10.0, length / 3.0);
  const double rise_threshold = settings.rise_lean_deg * std::numbers::pi / 180.0;
  std::vector<double> distance, first, last, rise;
  int flights = 0;
  for (const Trace& tr : traces) {
    if (tr.x_m.empty()) continue;
    distance.push_back(tr.x_m.back() - tr.x_m.front());
    if (const auto v = segment_speed(tr.t_s, tr.x_m, tr.x_m.front(), tr.x_m.front() + out.segment_m)) first.push_back(*v);
    if (const auto r = rise_distance(tr.x_m, tr.lean_rad, rise_threshold)) rise.push_back(*r);
    if (!tr.finished) continue;
    if (const auto v = segment_speed(tr.t_s, tr.x_m, length - out.segment_m, length, true)) last.push_back(*v);
    if (flight_in_every_stride(tr.x_m, tr.contacts, length - out.segment_m)) ++flights;
  }
  out.distance_m = mean_of(distance);
  out.first_speed_mps = mean_of(first);
  out.last_speed_mps = mean_of(last);
  out.rise_distance_m = mean_of(rise);
  out.rise_rate = static_cast<double>(rise.size()) / episodes;
  out.flight_rate = static_cast<double>(flights) / episodes;
  return out;
}

double DistanceTally::first_tenth() const {
  std::int64_t total = 0, n = 0;
  double sum = 0.0;
  for (const auto& [count, s] : per_iteration) total += count;
  for (const auto& [count, s] : per_iteration) {
    if (n > 0 && 10 * n >= total) break;
    n += count, sum += s;
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

double DistanceTally::last_tenth() const {
  std::int64_t total = 0, n = 0;
  double sum = 0.0;
  for (const auto& [count, s] : per_iteration) total += count;
  for (auto it = per_iteration.rbegin(); it != per_iteration.rend(); ++it) {
    if (n > 0 && 10 * n >= total) break;
    n += it->first, sum += it->second;
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

AccelerateStage::AccelerateStage(const AccelerateSettings& settings, std::vector<Json> starts, std::uint64_t seed,
                                 fs::path work_dir)
    : s_(settings), starts_(std::move(starts)), seed_(seed), work_dir_(std::move(work_dir)) {
  if (starts_.empty()) throw base::UserError("sprint accelerate: no start states");
  if (s_.primitive_weight == 0.0) return;
  if (s_.primitive.clips.empty())
    throw base::UserError("sprint accelerate: primitive_weight is " + std::to_string(s_.primitive_weight) +
                          " but primitive_clips is empty: the sport primitive needs reference runs");
  const sim::ModelPtr model = sim::load_shipped_model(SprintEnvSettings{}.model);
  primitive_ = std::make_shared<SportPrimitive>(strides_from_clips(model, SprintEnvSettings{}.control_hz, s_.primitive),
                                                s_.primitive, base::derive_seed(seed_, 7));
}

Json AccelerateStage::primitive_summary() const { return primitive_ ? primitive_->summary() : Json(nullptr); }

SprintEnvSettings AccelerateStage::env_settings() const {
  SprintEnvSettings e;
  e.preset = load_sprint_preset(s_.train.track);
  e.sim_hz = s_.train.sim_hz;
  e.handover_states = starts_;
  e.primitive = primitive_;
  e.preset.rewards.primitive = s_.primitive_weight;
  return e;
}

void AccelerateStage::build(const Json&) {
  SprintEnvSettings settings = env_settings();
  settings.log_distances = true;
  std::vector<std::unique_ptr<learn::Env>> copies;
  copies_.clear();
  for (int i = 0; i < s_.train.copies; ++i) {
    auto env = std::make_unique<SprintEnv>(settings);
    copies_.push_back(env.get());
    copies.push_back(std::move(env));
  }
  envs_ = std::make_unique<learn::VecEnv>(std::move(copies), s_.train.threads, base::derive_seed(seed_, 1));
}

Json AccelerateStage::learner_spec() const {
  return {{"algorithm", "ppo"}, {"preset", s_.train.ppo_preset}, {"config", s_.train.ppo}};
}

Json AccelerateStage::state() const {
  Json state = {{"distances", tally_.per_iteration}};
  if (primitive_ && s_.primitive.online) {  // Φ2 beside the checkpoint: the last two kept
    const std::string name = "primitive_phi2_" + std::to_string(adaptations_) + ".pt";
    primitive_->save_online(work_dir_ / name);
    std::error_code ignored;
    fs::remove(work_dir_ / ("primitive_phi2_" + std::to_string(adaptations_ - 2) + ".pt"), ignored);
    state["primitive"] = {{"phi2", name}, {"adaptations", adaptations_}, {"buffer", stride_buffer_}};
  }
  return state;
}

void AccelerateStage::load_state(const Json& state) {
  tally_.per_iteration = state.at("distances").get<std::vector<std::pair<std::int64_t, double>>>();
  if (primitive_ && s_.primitive.online && state.contains("primitive")) {
    const Json& p = state.at("primitive");
    primitive_->load_online(work_dir_ / p.at("phi2").get<std::string>());
    adaptations_ = p.at("adaptations").get<int>();
    stride_buffer_ = p.at("buffer").get<std::vector<std::vector<double>>>();
  }
}

void AccelerateStage::on_iteration(const character::Iteration& iteration, learn::Learner&, const character::MetricFn& send) {
  std::int64_t n = 0;
  double sum = 0.0;
  for (SprintEnv* env : copies_)
    for (const double d : env->take_episode_distances()) ++n, sum += d;
  tally_.per_iteration.emplace_back(n, sum);
  const auto steps = static_cast<double>(iteration.env_steps);
  if (n > 0) send("accelerate/train_distance_m", steps, sum / static_cast<double>(n));
  if (primitive_) adapt_primitive(steps, send);
}

// §3.2: the iteration's strides scored (their mean r_primitive / w) and, with `online`, Φ2 trained
// on the latest of them.
void AccelerateStage::adapt_primitive(double steps, const character::MetricFn& send) {
  std::vector<std::vector<double>> strides;
  for (SprintEnv* env : copies_)
    for (auto& stride : env->take_strides()) strides.push_back(std::move(stride));
  if (strides.empty()) return;
  double reward = 0.0;
  for (const auto& stride : strides) reward += primitive_->reward(stride) / static_cast<double>(strides.size());
  send("accelerate/primitive_reward", steps, reward);
  send("accelerate/strides", steps, static_cast<double>(strides.size()));
  if (!s_.primitive.online) return;
  for (auto& stride : strides) stride_buffer_.push_back(std::move(stride));
  const auto excess = static_cast<std::ptrdiff_t>(stride_buffer_.size()) - s_.primitive.online_buffer;
  if (excess > 0) stride_buffer_.erase(stride_buffer_.begin(), stride_buffer_.begin() + excess);
  primitive_->adapt(stride_buffer_);
  ++adaptations_;
}

character::Figures AccelerateStage::test(const character::TestRound& round, learn::Learner& learner,
                                         const character::MetricFn& send) {
  const auto samples = static_cast<double>(round.env_steps);
  SprintEnv env(env_settings());
  const RunEvaluation e = evaluate_runs(
      env, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); }, s_.train.eval_episodes,
      s_.train.eval_seed, s_);
  send("accelerate/return", samples, e.return_mean);
  send("accelerate/finish_rate", samples, e.finish_rate);
  send("accelerate/distance_m", samples, e.distance_m);
  send("accelerate/first_speed_mps", samples, e.first_speed_mps);
  send("accelerate/last_speed_mps", samples, e.last_speed_mps);
  send("accelerate/rise_distance_m", samples, e.rise_distance_m);
  send("accelerate/flight_rate", samples, e.flight_rate);
  char line[200];
  std::snprintf(line, sizeof line, "accelerate: sample %.0f: return %.2f, finishes %.2f, distance %.2f m, speeds %.2f / %.2f m/s",
                samples, e.return_mean, e.finish_rate, e.distance_m, e.first_speed_mps, e.last_speed_mps);
  base::log_info(line);
  return {{"finish_rate", e.finish_rate}, {"distance_m", e.distance_m}, {"return", e.return_mean}};
}

std::optional<character::ExportReason> AccelerateStage::export_rule(const character::ExportRecord& tested,
                                                                    const character::ExportRecord* exported) {
  return character::best_by(tested, exported, {{"finish_rate"}, {"distance_m"}});
}

void AccelerateStage::record(const character::Recording& r) {
  SprintEnv env(env_settings());
  final_ = evaluate_runs(
      env, [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); }, s_.train.final_episodes,
      base::derive_seed(s_.train.eval_seed, 1), s_, r.rollouts / "accelerate");
  const auto samples = static_cast<double>(r.exported.env_steps);
  r.send("accelerate/final_finish_rate", samples, final_.finish_rate);
  r.send("accelerate/final_last_speed_mps", samples, final_.last_speed_mps);
  r.send("accelerate/final_rise_distance_m", samples, final_.rise_distance_m);
  trajectory_ = r.rollouts / "accelerate" / "trajectory_0.jsonl";
  handovers_ = r.file.parent_path() / "dip_starts.json";
  save_handover_states(handovers_.string(), final_.handovers);
}

AccelerateOutcome run_accelerate_trial(const AccelerateSettings& settings, std::vector<Json> starts,
                                       const character::StageRun& run) {
  AccelerateStage stage(settings, std::move(starts), run.seed, run.work_dir);
  const character::StageOutcome done = character::run_training_stage(stage,
                                                                     {.name = "sprint accelerate",
                                                                      .total_steps = settings.train.total_samples,
                                                                      .steps_per_iteration = 1,
                                                                      .test_every = settings.train.eval_every,
                                                                      .checkpoint_every = settings.train.checkpoint_every,
                                                                      .warm_start = settings.train.warm_start},
                                                                     run);
  AccelerateOutcome out;
  out.final = stage.final_evaluation();
  out.distances = stage.distances();
  out.policy = done.policy;
  out.trajectory = stage.trajectory();
  out.handovers = stage.handovers_file();
  out.samples = done.env_steps;
  out.primitive = stage.primitive_summary();
  return out;
}

}  // namespace podium::tasks::sprint
