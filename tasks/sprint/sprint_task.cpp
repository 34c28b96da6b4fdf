// The sprint task plugin (sprint seed 002, "Learn to Sprint 100 Metres"). Stages, chosen by the
// config key `stage`: "start" (§3.1: PPO imitating our keyframed crouch starts, from the blocks to
// the first landing; its landing states are stage 2's start set) and "accelerate" (§3.2: one PPO
// policy from those landings to the line; its snapshots before the line are the dip stage's),
// "dip" (§3.3: one candidate (d_dip, θ_dip) of the stage's CMA-ES, on the frozen accelerate
// policy from those snapshots) and "race" (the race report over DR episodes, race.h). README.md
// gives the metrics and presets.
#include <cstdio>
#include <fstream>

#include "dip.h"
#include "podium/learn/frozen_policy.h"
#include "podium/plugins/export.h"
#include "race.h"
#include "train_accelerate.h"
#include "train_start.h"

namespace podium::tasks::sprint {

using base::Json;

namespace {

struct TaskConfig {
  std::string stage = "start";
  StartTrainSettings start;
  AccelerateSettings accelerate;
  RaceSettings race;
  DipSettings dip;
};

TaskConfig read_task_config(base::ConfigReader& r) {
  TaskConfig c;
  c.stage =
      r.choice("stage", c.stage, {"start", "accelerate", "dip", "race"},
               "start: the Start phase (§3.1), PPO on r_base + λ_i·r_imitation of our crouch starts to the first landing; "
               "accelerate: Acceleration + Top Speed (§3.2), PPO from the start trial's landings to the line on r_base + "
               "r_mass + r_diag + r_mirror + r_primitive; dip: the Dip Finish (§3.3), one candidate (d_dip, θ_dip) on the frozen "
               "accelerate "
               "policy from its snapshots before the line; race: the race report, the best start and accelerate trials over DR "
               "episodes (race.h)");
  c.start = read_start_train_settings(r);
  c.accelerate.train = c.start;
  read_accelerate_settings(r, c.accelerate);
  c.dip.track = c.start.track;
  c.dip.sim_hz = c.start.sim_hz;
  c.dip.seed = base::derive_seed(c.start.eval_seed, 3);
  read_dip_settings(r, c.dip);
  c.race.track = c.start.track, c.race.sim_hz = c.start.sim_hz, c.race.rise_lean_deg = c.accelerate.rise_lean_deg;
  c.race.start_clips = c.start.clips;
  read_race_settings(r, c.race);
  if (c.race.seed == c.start.eval_seed) r.fail("race_seed", "must differ from eval_seed (the race's episodes are held out)");
  return c;
}

TaskConfig config_from(const Json& config) { return base::ConfigReader::parse(config, "sprint config", read_task_config); }

// smoke: seconds (16-16 networks, 4 iterations of 64 samples, 2 copies, 150 Hz simulation; the
// mechanics only, no start is learnt). quick: 2 cores (256-128, 1024 samples per iteration,
// 600 Hz until a lower rate is measured to give the same outcomes). paper: the jump's paper scale
// (4096 samples per iteration, 1024-512, the seed gives no settings), budgets for Slurm. quick and
// paper weigh r_primitive 2 per completed stride (ours: a stride lasts about 20 control steps, each
// of which earns r_s = 1; smoke leaves it off), so their accelerate stage needs primitive_clips.
Json presets() {
  return {{"smoke",
           {{"track", "smoke"},
            {"ppo_preset", "quick"},
            {"ppo", {{"hidden", {16, 16}}, {"rollout_steps", 32}, {"epochs", 2}, {"minibatch_size", 32}}},
            {"copies", 2},
            {"threads", 1},
            {"total_samples", 256},
            {"sim_hz", 150.0},
            {"eval_every", 2},
            {"eval_episodes", 2},
            {"final_episodes", 4},
            {"checkpoint_every", 1},
            {"dip_episodes", 4}}},
          {"quick",
           {{"track", "quick"},
            {"ppo_preset", "paper"},
            {"ppo", {{"hidden", {256, 128}}, {"rollout_steps", 256}}},
            {"copies", 4},
            {"threads", 2},
            {"total_samples", 2'000'000},
            {"sim_hz", 600.0},
            {"eval_every", 25},
            {"primitive_weight", 2.0},
            {"eval_episodes", 8},
            {"final_episodes", 20},
            {"checkpoint_every", 10},
            {"dip_episodes", 10}}},
          {"paper",
           {{"track", "paper"},
            {"ppo_preset", "paper"},
            {"ppo", {{"hidden", {1024, 512}}, {"rollout_steps", 256}}},
            {"copies", 16},
            {"threads", 16},
            {"total_samples", 5000LL * 4096},
            {"sim_hz", 600.0},
            {"eval_every", 50},
            {"primitive_weight", 2.0},
            {"eval_episodes", 16},
            {"final_episodes", 100},
            {"checkpoint_every", 10},
            {"dip_episodes", 32}}}};
}

Json start_metrics() {
  const plugins::MetricShape samples{.x = {"samples", ""}}, rate{.x = {"samples", ""}, .rate = true};
  const plugins::MetricShape final_value{.x = {"samples", ""}, .evaluation = true},
      final_rate{.x = {"samples", ""}, .evaluation = true, .rate = true};
  Json m = {
      plugins::metric_entry("start/return", "", "mean return of the test starts (deterministic policy)", samples),
      plugins::metric_entry("start/landing_rate", "", "test starts that reached the first landing", rate),
      plugins::metric_entry("start/min_reference_landing_rate", "",
                            "the lowest landing rate of a reference drawn in the test (the export's first criterion)", rate),
      plugins::metric_entry("start/tracking_error_rad", "rad",
                            "mean per-joint rotation error against the reference, √(Σ_j ‖q̂_j ⊖ q_j‖² / J) per step", samples),
      plugins::metric_entry("start/com_speed_ratio", "", "the COM's forward speed at the landing over the reference's", samples),
      plugins::metric_entry("start/final_landing_rate", "", "the exported policy's landings over final_episodes starts",
                            final_rate),
      plugins::metric_entry("start/final_tracking_error_rad", "rad", "the exported policy's mean per-joint rotation error",
                            final_value),
      plugins::metric_entry("start/final_com_speed_ratio", "",
                            "the exported policy's COM speed at the landing over the reference's", final_value)};
  for (const Json& t : character::time_metric_entries()) m.push_back(t);
  return m;
}

plugins::RunResult run_start(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  if (!request.inputs.empty()) throw base::UserError("sprint start: takes no input trials");
  const StartOutcome out =
      run_start_trial(c.start, {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});
  plugins::RunResult result;
  result.objectives = {out.final.landing_rate, -out.final.tracking_error_rad};
  result.artifacts = {{"policy", out.policy}, {"landings", out.landings}};
  if (std::filesystem::exists(out.trajectory)) result.artifacts.push_back({"trajectory", out.trajectory});
  result.info = out.final.to_json();
  result.info["samples"] = out.samples;
  result.info["summary"] = {{"landing rate", out.final.landing_rate},
                            {"tracking error rad", out.final.tracking_error_rad},
                            {"COM speed at landing / reference's", out.final.com_speed_ratio},
                            {"landing states", out.final.landings.size()}};
  return result;
}

Json accelerate_metrics() {
  const plugins::MetricShape samples{.x = {"samples", ""}}, rate{.x = {"samples", ""}, .rate = true};
  const plugins::MetricShape final_value{.x = {"samples", ""}, .evaluation = true},
      final_rate{.x = {"samples", ""}, .evaluation = true, .rate = true};
  Json m = {
      plugins::metric_entry("accelerate/train_distance_m", "m", "mean distance of the training episodes ended in the iteration",
                            samples),
      plugins::metric_entry("accelerate/primitive_reward", "",
                            "mean exp(−k·KL) of the training strides ended in the iteration (a sport primitive)", samples),
      plugins::metric_entry("accelerate/strides", "", "training strides ended in the iteration (a sport primitive)", samples),
      plugins::metric_entry("accelerate/return", "", "mean return of the test runs (deterministic policy)", samples),
      plugins::metric_entry("accelerate/finish_rate", "", "test runs over the track without a fall or leaving the lane", rate),
      plugins::metric_entry("accelerate/distance_m", "m", "mean distance the root covered in a test run", samples),
      plugins::metric_entry("accelerate/first_speed_mps", "m/s", "mean speed over the first 10 m (a third of a shorter track)",
                            samples),
      plugins::metric_entry("accelerate/last_speed_mps", "m/s",
                            "finishers' mean speed over the last 10 m (a third of a shorter track)", samples),
      plugins::metric_entry("accelerate/rise_distance_m", "m",
                            "mean x where the trunk's lean from vertical drops below 20° for good (runs that rose)", samples),
      plugins::metric_entry("accelerate/flight_rate", "",
                            "test runs that finished with a flight phase in every stride of the last segment", rate),
      plugins::metric_entry("accelerate/final_finish_rate", "", "the exported policy's finish rate over final_episodes runs",
                            final_rate),
      plugins::metric_entry("accelerate/final_last_speed_mps", "m/s", "the exported policy's speed over the last segment",
                            final_value),
      plugins::metric_entry("accelerate/final_rise_distance_m", "m", "the exported policy's rise distance", final_value)};
  for (const Json& t : character::time_metric_entries()) m.push_back(t);
  return m;
}

// The start set: the input start trial's landings; when it landed nowhere (or no start trial is
// given) the documented fallback, the crouch starts' last frames just past the line.
std::vector<Json> accelerate_starts(const TaskConfig& c, const plugins::RunRequest& request, std::string& source) {
  if (request.inputs.size() > 1)
    throw base::UserError("sprint accelerate: takes at most one input trial (a start trial's landings), got " +
                          std::to_string(request.inputs.size()));
  if (!request.inputs.empty()) {
    const plugins::InputTrial& in = request.inputs.front();
    if (!in.artifacts.count("landings"))
      throw base::UserError("sprint accelerate: input trial " + in.stage + "/" + std::to_string(in.trial_index) +
                            " has no artifact landings (is it a sprint start trial?)");
    std::vector<Json> states = load_handover_states(in.artifacts.at("landings").string());
    if (!states.empty()) {
      source = "landings of " + in.stage + "/" + std::to_string(in.trial_index);
      return states;
    }
  }
  source = request.inputs.empty() ? "fallback: no start trial given" : "fallback: the start trial landed in no final episode";
  return fallback_starts(c.start.track, c.start.sim_hz);
}

plugins::RunResult run_accelerate(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  std::string source;
  std::vector<Json> starts = accelerate_starts(c, request, source);
  const std::size_t count = starts.size();
  const AccelerateOutcome out = run_accelerate_trial(
      c.accelerate, std::move(starts), {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});
  plugins::RunResult result;
  result.objectives = {out.final.finish_rate, out.final.distance_m};
  result.artifacts = {{"policy", out.policy}, {"dip_starts", out.handovers}};
  if (std::filesystem::exists(out.trajectory)) result.artifacts.push_back({"trajectory", out.trajectory});
  result.info = out.final.to_json();
  result.info["samples"] = out.samples;
  result.info["starts"] = {{"source", source}, {"fallback", source.starts_with("fallback")}, {"count", count}};
  result.info["train_distance_first_tenth_m"] = out.distances.first_tenth();
  result.info["train_distance_last_tenth_m"] = out.distances.last_tenth();
  result.info["primitive"] = out.primitive;
  result.info["summary"] = {
      {"finish rate", out.final.finish_rate},
      {"distance m", out.final.distance_m},
      {"speed first / last segment m/s", Json::array({out.final.first_speed_mps, out.final.last_speed_mps})},
      {"rise distance m", out.final.rise_distance_m},
      {"flight in every last-segment stride", out.final.flight_rate},
      {"training distance first / last tenth m", Json::array({out.distances.first_tenth(), out.distances.last_tenth()})},
      {"starts", source},
      {"dip snapshots", out.final.handovers.size()}};
  return result;
}

// The race stage: its inputs are the best start trial (artifact landings), the best accelerate
// trial (artifact dip_starts) and, optionally, the best dip trial (params d_dip_m, theta_dip_deg),
// in any order. Without a dip trial the dip is config (race_dip_*); with one, the config sets none.
struct RaceInputs {
  RacePolicies policies;
  std::optional<DipParams> dip;
  std::string dip_source = "none";
};

RaceInputs race_inputs(const TaskConfig& c, const plugins::RunRequest& request) {
  RaceInputs p;
  if (c.race.dip) p.dip = c.race.dip, p.dip_source = "config (race_dip_*)";
  for (const plugins::InputTrial& in : request.inputs) {
    const std::string who = in.stage + "/" + std::to_string(in.trial_index);
    if (in.params.contains("d_dip_m") && in.params.contains("theta_dip_deg")) {
      if (c.race.dip)
        throw base::UserError("sprint race: input trial " + who +
                              " is a dip trial and race_dip_distance_m is set in the config; give one or the other");
      p.dip = DipParams{in.params.at("d_dip_m").get<double>(), in.params.at("theta_dip_deg").get<double>()};
      p.dip_source = "dip trial " + who;
      continue;
    }
    if (!in.artifacts.count("policy")) throw base::UserError("sprint race: input trial " + who + " has no artifact policy");
    if (in.artifacts.count("landings")) p.policies.start = in.artifacts.at("policy");
    else if (in.artifacts.count("dip_starts")) p.policies.accelerate = in.artifacts.at("policy");
    else
      throw base::UserError("sprint race: input trial " + who +
                            " is neither a start (landings), an accelerate (dip_starts) nor a dip (d_dip_m) trial");
  }
  if (p.policies.start.empty() || p.policies.accelerate.empty())
    throw base::UserError(
        "sprint race: needs a start trial and an accelerate trial as inputs (\"inputs\": {\"stage\": "
        "[\"start\", \"accelerate\", \"dip\"], \"select\": \"best\"}; the dip is optional), got " +
        std::to_string(request.inputs.size()));
  return p;
}

void describe_race(const TaskConfig& c, Json& d) {
  const plugins::MetricShape per_episode{.x = {"episode", ""}, .evaluation = true};
  d["metrics"] = {
      plugins::metric_entry("race/finish_time_s", "s", "each DR episode's finish time (torso at the line; finishers)",
                            per_episode),
      plugins::metric_entry("race/top_speed_mps", "m/s", "each episode's top speed", per_episode),
      plugins::metric_entry("race/steps", "", "each finisher's step count to the line", per_episode),
      plugins::metric_entry("race/headwind_finish_time_s", "s", "each episode's finish time in the wind check's headwind",
                            per_episode),
      plugins::metric_entry("race/tailwind_finish_time_s", "s", "each episode's finish time in its tailwind", per_episode)};
  const double length = load_sprint_preset(c.race.track).track.length_m;
  d["features"] = {{{"name", "step_length_m"},
                    {"low", 0.0},
                    {"high", 3.0},
                    {"metric", "euclidean"},
                    {"unit", "m"},
                    {"description", "mean step length"}},
                   {{"name", "step_frequency_hz"},
                    {"low", 0.0},
                    {"high", 6.0},
                    {"metric", "euclidean"},
                    {"unit", "Hz"},
                    {"description", "mean step frequency"}},
                   {{"name", "rise_distance_m"},
                    {"low", -2.0},
                    {"high", length},
                    {"metric", "euclidean"},
                    {"unit", "m"},
                    {"description", "mean rise distance (the track's length when no episode rose)"}}};
  plugins::set_objectives(
      d, Json::array({plugins::objective_entry("minus_mean_finish_time_s", "s",
                                               "minus the mean finish time over the DR episodes, a fall or lane exit counted at "
                                               "the race's time limit"),
                      plugins::objective_entry("finish_rate", "", "the DR episodes that reached the line")}));
}

plugins::RunResult run_race_stage(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  const RaceInputs in = race_inputs(c, request);
  RaceSettings settings = c.race;
  settings.dip = in.dip;
  const RaceReport report =
      run_race(settings, in.policies, request.work_dir, request.cancel, [&](double f) { sink.progress(f); });
  for (const RaceEpisode& e : report.episodes) {
    if (e.finish_time_s)
      sink.metric("race/finish_time_s", e.index, *e.finish_time_s), sink.metric("race/steps", e.index, e.steps);
    if (e.top_speed) sink.metric("race/top_speed_mps", e.index, e.top_speed->speed_mps);
  }
  for (const RaceEpisode& e : report.headwind)
    if (e.finish_time_s) sink.metric("race/headwind_finish_time_s", e.index, *e.finish_time_s);
  for (const RaceEpisode& e : report.tailwind)
    if (e.finish_time_s) sink.metric("race/tailwind_finish_time_s", e.index, *e.finish_time_s);
  const std::filesystem::path json = request.work_dir / "race.json", text = request.work_dir / "race.txt";
  base::write_json_file_atomic(json, report.to_json());
  std::ofstream(text) << report.text_table();
  const Json summary = report.summary();
  plugins::RunResult result;
  result.objectives = {-summary["mean_race_time_s"].get<double>(), summary["finish_rate"].get<double>()};
  const auto feature = [&](const char* key, double none) { return summary[key].is_null() ? none : summary[key].get<double>(); };
  result.features = {feature("mean_step_length_m", 0.0), feature("mean_step_frequency_hz", 0.0),
                     feature("mean_rise_distance_m", report.length_m)};
  result.artifacts = {{"race", json}, {"race_table", text}};
  for (std::size_t k = 0; k < report.motions.size(); ++k)
    result.artifacts.push_back({k == 0 ? "trajectory" : "trajectory_" + std::to_string(k), report.motions[k]});
  result.info = summary;
  result.info["dip_source"] = in.dip_source;
  const Json& wind = summary["wind_check"];
  const Json& dip = summary["dip_check"];
  result.info["summary"] = {
      {"finish rate", summary["finish_rate"]},
      {"finish time mean / sd s", Json::array({summary["mean_finish_time_s"], summary["std_finish_time_s"]})},
      {"top speed m/s at m", Json::array({summary["mean_top_speed_mps"], summary["mean_top_speed_at_m"]})},
      {"steps mean / sd", Json::array({summary["mean_steps"], summary["std_steps"]})},
      {"step length m, frequency Hz", Json::array({summary["mean_step_length_m"], summary["mean_step_frequency_hz"]})},
      {"rise distance m", summary["mean_rise_distance_m"]},
      {"headwind − tailwind s (pairs)", wind.is_null() ? Json(nullptr) : Json::array({wind["mean_difference_s"], wind["pairs"]})},
      {"dip gain s ± s.e. (pairs, faster, falls added)",
       dip.is_null()
           ? Json(nullptr)
           : Json::array({dip["mean_gain_s"], dip["gain_standard_error_s"], dip["pairs"], dip["improved"], dip["added_falls"]})}};
  result.info["table"] = report.result_table();
  return result;
}

Json dip_metrics() {
  const plugins::MetricShape per_episode{.x = {"episode", ""}, .evaluation = true};
  return {plugins::metric_entry("dip/time_s", "s",
                                "time from the episode's snapshot to the finish with the dip (a fall: the penalty)", per_episode),
          plugins::metric_entry("dip/no_dip_time_s", "s", "the same without the dip (the accelerate policy alone)", per_episode)};
}

Json dip_params() {
  return {{{"name", "d_dip_m"}, {"low", 1.0}, {"high", 5.0}}, {{"name", "theta_dip_deg"}, {"low", 0.0}, {"high", 90.0}}};
}

Json dip_features() {
  return {{{"name", "d_dip_m"},
           {"low", 1.0},
           {"high", 5.0},
           {"metric", "euclidean"},
           {"unit", "m"},
           {"description", "the root's distance to the line when the dip fires"}},
          {{"name", "theta_dip_deg"},
           {"low", 0.0},
           {"high", 90.0},
           {"metric", "euclidean"},
           {"unit", "°"},
           {"description", "the dip's tilt, added to both hips' flexion targets"}}};
}

// The accelerate trial handed over: its policy and its snapshots before the line, or (none got
// that far: the smoke campaign's untrained stage 2) the documented fallback.
struct DipInputs {
  std::filesystem::path policy;
  std::vector<Json> snapshots;
  std::string source;
};

DipInputs dip_inputs(const TaskConfig& c, const plugins::RunRequest& request) {
  if (request.inputs.size() != 1)
    throw base::UserError("sprint dip: takes one input trial (an accelerate trial's policy and dip_starts), got " +
                          std::to_string(request.inputs.size()));
  const plugins::InputTrial& in = request.inputs.front();
  const std::string name = in.stage + "/" + std::to_string(in.trial_index);
  for (const char* artifact : {"policy", "dip_starts"})
    if (!in.artifacts.count(artifact))
      throw base::UserError("sprint dip: input trial " + name + " has no artifact " + artifact +
                            " (is it a sprint accelerate trial?)");
  DipInputs out{in.artifacts.at("policy"), load_handover_states(in.artifacts.at("dip_starts").string()), ""};
  out.source = "dip_starts of " + name;
  if (out.snapshots.empty()) {
    const double before = c.accelerate.handover_before_line_m;
    out.snapshots = fallback_starts(c.start.track, c.start.sim_hz, load_sprint_preset(c.start.track).track.length_m - before);
    out.source = "fallback: " + name + " reached no snapshot; the crouch starts' landings moved to the snapshot distance";
  }
  return out;
}

double param(const plugins::RunRequest& request, const std::string& name, double low, double high) {
  const Json& p = request.params;
  if (!p.contains(name) || !p.at(name).is_number() || !(p.at(name).get<double>() >= low && p.at(name).get<double>() <= high))
    throw base::UserError("sprint dip: params." + name + ": " + (p.contains(name) ? p.at(name).dump() : "missing") +
                          " is not a number in [" + base::Json(low).dump() + ", " + base::Json(high).dump() + "]");
  return p.at(name).get<double>();
}

// Per episode, paired: no dip, the dip, the gain; and the result table.
Json dip_table(const std::vector<DipEpisode>& none, const std::vector<DipEpisode>& dip) {
  Json rows = Json::array();
  for (std::size_t i = 0; i < dip.size(); ++i)
    rows.push_back({static_cast<int>(i), dip[i].draw.wind_mps, dip[i].draw.friction, none[i].time_s, dip[i].time_s,
                    none[i].time_s - dip[i].time_s, dip[i].fired_step >= 0 ? Json(dip[i].fired_distance_m) : Json(nullptr),
                    none[i].outcome + " / " + dip[i].outcome});
  return plugins::result_table(
      "dip episodes (time from the snapshot; a fall scores the penalty)",
      {plugins::table_column("episode"), plugins::table_column("wind", "m/s"), plugins::table_column("μ"),
       plugins::table_column("no dip", "s"), plugins::table_column("dip", "s"), plugins::table_column("gain", "s"),
       plugins::table_column("fired at", "m"), plugins::table_column("outcome: no dip / dip")},
      rows);
}

plugins::RunResult run_dip(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  const DipParams dip{param(request, "d_dip_m", 1.0, 5.0), param(request, "theta_dip_deg", 0.0, 90.0)};
  const DipInputs in = dip_inputs(c, request);
  const learn::FrozenPolicy frozen(in.policy);
  const character::PolicyFn policy = [&](std::span<const double> o, std::span<double> a) { frozen.act(o, a); };
  DipEvaluator evaluator(c.dip, in.snapshots);
  if (frozen.observation_size() != evaluator.env().observation_space().size() ||
      frozen.action_size() != evaluator.env().action_space().size())
    throw base::UserError("sprint dip: policy " + in.policy.string() + " maps " + std::to_string(frozen.observation_size()) +
                          " observations to " + std::to_string(frozen.action_size()) + " actions; the sprint env has " +
                          std::to_string(evaluator.env().observation_space().size()) + " and " +
                          std::to_string(evaluator.env().action_space().size()) + " (is it an accelerate trial's policy?)");
  const std::vector<DipEpisode> none = evaluator.run(policy, std::nullopt, request.cancel);
  sink.progress(0.5);
  const std::vector<DipEpisode> with = evaluator.run(policy, dip, request.cancel);
  const DipSummary a = DipSummary::of(none), b = DipSummary::of(with);
  int improved = 0, added_falls = 0;
  Json episodes = Json::array();
  for (std::size_t i = 0; i < with.size(); ++i) {
    sink.metric("dip/time_s", static_cast<double>(i), with[i].time_s);
    sink.metric("dip/no_dip_time_s", static_cast<double>(i), none[i].time_s);
    if (with[i].time_s < none[i].time_s) ++improved;
    if (none[i].finished && !with[i].finished) ++added_falls;
    episodes.push_back({{"no_dip", none[i].to_json()}, {"dip", with[i].to_json()}});
  }
  const std::filesystem::path file = request.work_dir / "dip_episodes.json";
  base::write_json_file_atomic(file, episodes);
  plugins::RunResult result;
  result.objectives = {-b.mean_time_s, b.finish_rate};
  result.features = {dip.distance_m, dip.angle_deg};
  result.artifacts = {{"episodes", file}};
  result.info = {
      {"dip", b.to_json()},
      {"no_dip", a.to_json()},
      {"gain_s", a.mean_time_s - b.mean_time_s},
      {"improved", improved},
      {"added_falls", added_falls},
      {"episodes", with.size()},
      {"fall_penalty_s", evaluator.fall_penalty_s()},
      {"chest", c.dip.chest},
      {"starts", {{"source", in.source}, {"fallback", in.source.starts_with("fallback")}, {"count", in.snapshots.size()}}}};
  result.info["table"] = dip_table(none, with);
  char gain[160];
  std::snprintf(gain, sizeof gain, "%.4f s (%d of %zu episodes faster, %d falls added)", a.mean_time_s - b.mean_time_s, improved,
                with.size(), added_falls);
  result.info["summary"] = {{"d_dip m", dip.distance_m},
                            {"θ_dip °", dip.angle_deg},
                            {"mean time with the dip s", b.mean_time_s},
                            {"without s", a.mean_time_s},
                            {"gain", gain},
                            {"finish rate with / without", Json::array({b.finish_rate, a.finish_rate})},
                            {"starts", in.source}};
  sink.progress(1.0);
  return result;
}

}  // namespace

class SprintTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const TaskConfig c = config_from(config);
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_task_config(r); });
    const bool start = c.stage == "start", dip = c.stage == "dip";
    Json d = {{"params", dip ? dip_params() : Json::array()},
              {"features", dip ? dip_features() : Json::array()},
              {"metrics", start ? start_metrics()
                          : dip ? dip_metrics()
                                : accelerate_metrics()}};
    if (dip)
      plugins::set_objectives(
          d, Json::array({plugins::objective_entry("minus_time_s", "s",
                                                   "minus the mean time from the snapshots before the line to the finish with "
                                                   "the dip (a fall scores the preset's penalty): higher is faster"),
                          plugins::objective_entry("finish_rate", "", "the dip's episodes that reached the line")}));
    else if (start)
      plugins::set_objectives(
          d,
          Json::array({plugins::objective_entry("landing_rate", "", "the exported policy's starts that reach the first landing"),
                       plugins::objective_entry("minus_tracking_error_rad", "rad",
                                                "minus its mean per-joint rotation error against the reference")}));
    else
      plugins::set_objectives(
          d, Json::array({plugins::objective_entry("finish_rate", "", "the exported policy's runs over the track without a fall"),
                          plugins::objective_entry("distance_m", "m", "the mean distance its runs covered")}));
    if (c.stage == "race") describe_race(c, d);
    d["presets"] = presets();
    d["config"] = accepted;
    d["config_defaults"] = base::ConfigReader::defaults(accepted);
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const TaskConfig c = config_from(request.config);
    if (c.stage == "race") return run_race_stage(c, request, sink);
    if (c.stage == "dip") return run_dip(c, request, sink);
    return c.stage == "start" ? run_start(c, request, sink) : run_accelerate(c, request, sink);
  }
};

}  // namespace podium::tasks::sprint

PODIUM_EXPORT_TASK(podium::tasks::sprint::SprintTask, "sprint")
