// The jump task plugin (thesis ch. 3). One plugin, two stages chosen by the config key
// `stage`: "explore" (Stage 1, §3.5.1: the take-off features are the params BDS searches; the
// feature is the 1-D up-angle at the bar) and "novel" (Stage 2, §3.5.2: one Stage 1 trial per
// trial, warm-started from its policy, rewarded for a bar-frame rotation unlike those found).
// `kind` picks the high jump or the obstacle jump. README.md gives the metrics and the presets.

#include <cmath>
#include <numbers>

#include "captured_techniques.h"
#include "podium/plugins/export.h"
#include "pose_prior.h"
#include "shipped_jumps.h"
#include "train_jump.h"
#include "train_runup.h"

namespace podium::tasks::jump {

using base::Json;

namespace {

struct TaskConfig {
  std::string stage = "explore";
  TrainSettings train;
  PosePriorSettings pose;            ///< the pose_vae stage's training
  std::vector<ShippedJump> shipped;  ///< the evaluate stage's policies
  std::string captured_motions;      ///< the captured techniques' folder ("": no labels)
  std::vector<TakeoffFeature> box;   ///< the ranges Stage 1 searches: takeoff_features(kind), narrowed by `takeoff_box`
  RunupSettings runup;               ///< the runup stage's (runup_*.{h,cpp})
};

// `takeoff_box`: {feature: [low, high]} replaces a take-off feature's default range (takeoff.h).
// Read raw, then by the kind's features: the describing reader must not list one kind's features
// as every config's defaults.
std::vector<TakeoffFeature> read_takeoff_box(base::ConfigReader& r, JumpKind kind) {
  std::vector<TakeoffFeature> box = takeoff_features(kind);
  const Json ranges = r.raw_object("takeoff_box",
                                   "the take-off features' search ranges, {name: [low, high]}; a feature left out "
                                   "keeps its default (takeoff.h)");
  base::ConfigReader b(ranges, r.path_of("takeoff_box"), "jump config");
  for (TakeoffFeature& f : box) {
    const std::vector<double> range = b.numbers(f.name, {f.low, f.high}, {}, "[low, high] in " + f.unit);
    if (range.size() != 2 || !(range[0] < range[1])) b.fail(f.name, "must be [low, high] with low < high");
    f.low = range[0];
    f.high = range[1];
  }
  b.finish();
  return box;
}

TaskConfig read_task_config(base::ConfigReader& r) {
  TaskConfig c;
  c.stage = r.choice(
      "stage", c.stage, {"pose_vae", "explore", "novel", "evaluate", "runup"},
      "pose_vae: trains the P-VAE (§3.4.2) the jumps act through; explore: Stage 1 (§3.5.1), params = take-off "
      "features, feature = up-angle, optional input: a pose_vae trial; novel: Stage 2 (§3.5.2), one input trial of an "
      "explore stage, its policy warm-started (and its P-VAE), feature = bar-frame rotation; evaluate: final_jumps jumps of "
      "the `shipped` policies (trial i: entry i mod n), feature = up-angle; runup: the run-up (§3.6.1) to one input trial's "
      "take-off state (inputs with \"per_trial\": \"each\") or, without inputs, to a `shipped` entry's (trial i: entry i mod "
      "n), then its full jump");
  c.train = read_train_settings(r);
  c.box = read_takeoff_box(r, c.train.env.kind);
  c.pose = read_pose_prior_settings(r);
  c.pose.model = c.train.env.model;
  c.shipped = read_shipped_jumps(r, c.train.env.kind);
  RunupSettings jump;  // the jump's athlete, foot and simulation rate
  jump.kind = c.train.env.kind, jump.model = c.train.env.model, jump.takeoff_foot = c.train.env.takeoff_foot,
  jump.sim_hz = c.train.env.sim_hz;
  c.runup = read_runup_settings(r, jump);
  c.captured_motions =
      r.path("captured_motions", c.captured_motions,
             "folder of the captured Fosbury flop, straddle and scissor jumps (DeepMimic format, e.g. "
             "data/motions/beyond of the authors' arpspoof/Jump): an explore trial is labelled by its nearest technique; "
             "\"\": no label");
  if (!c.captured_motions.empty() && !std::filesystem::is_directory(c.captured_motions))
    r.fail("captured_motions", "\"" + c.captured_motions + "\" is not a folder");
  return c;
}

TaskConfig config_from(const Json& config) { return base::ConfigReader::parse(config, "jump config", read_task_config); }

// smoke: seconds per trial (16-16 networks, 4 iterations of 64 samples, 2 copies, a 2-epoch P-VAE;
// mechanics only: no jump is learnt; the run-up hands over 0.3 s into the reference run, so that an
// untrained run-up reaches the take-off and the full jump runs too). The P-VAE: quick 600 epochs of the shipped 2,400 poses
// (about the thesis's number of updates, 80 epochs of 20,000 poses; ≈ 50 s), paper 80 epochs of the poses the user points
// `pose_set` at (the thesis's: arpspoof/Jump's data/vae/txt). quick: 2 cores, about 10 min per trial on one core (see README.md
// "Presets": 256-128 ReLU, 1024 samples per iteration, 150 Hz simulation, measured to give 600 Hz's outcomes). paper: §3.6.2
// (4096 samples per iteration = 16 copies × 256, 1024-512 ReLU, 5 epochs of 256, γ = 1, λ = 0.95, clip 0.02, LRs 2.5e-5 / 1e-2,
// 12,000 iterations, 600 Hz).
Json presets() {
  return {{"smoke",
           {{"ppo_preset", "quick"},
            {"ppo", {{"hidden", {16, 16}}, {"rollout_steps", 32}, {"epochs", 2}, {"minibatch_size", 32}, {"gamma", 1.0}}},
            {"copies", 2},
            {"threads", 1},
            {"total_samples", 256},
            {"sim_hz", 150.0},
            {"eval_every", 2},
            {"eval_jumps", 2},
            {"final_jumps", 2},
            {"checkpoint_every", 1},
            {"vae_epochs", 2},
            {"runup_takeoff_time_s", 0.3}}},
          {"quick",
           {{"ppo_preset", "paper"},
            {"ppo",
             {{"hidden", {256, 128}},
              {"rollout_steps", 256},
              {"sigma_anneal_steps", 400'000},
              {"policy_lr_start", 1e-4},
              {"policy_lr_end", 1e-4},
              {"clip", 0.1}}},
            {"copies", 4},
            {"threads", 1},
            {"total_samples", 400'000},
            {"sim_hz", 150.0},
            {"eval_every", 25},
            {"eval_jumps", 5},
            {"final_jumps", 20},
            {"checkpoint_every", 10},
            {"vae_epochs", 600},
            {"runup_lead_s", 0.5}}},
          {"paper",
           {{"ppo_preset", "paper"},
            {"ppo", {{"rollout_steps", 256}}},
            {"copies", 16},
            {"threads", 16},
            {"total_samples", 12'000LL * 4096},
            {"sim_hz", 600.0},
            {"eval_every", 50},
            {"eval_jumps", 5},
            {"final_jumps", 20},
            {"checkpoint_every", 10}}}};
}

Json metrics() {
  // Training's curves over samples (environment steps of every copy); the final policy's
  // evaluation jumps, one point each at the samples trained.
  const plugins::MetricShape samples{.x = {"samples", ""}}, samples_rate{.x = {"samples", ""}, .rate = true};
  const plugins::MetricShape final_rate{.x = {"samples", ""}, .evaluation = true, .rate = true};
  Json metrics = {
      plugins::metric_entry("train/avg_reward", "", "the iteration's curriculum score (curriculum_score)", samples),
      plugins::metric_entry("train/episodes", "", "episodes ended in the iteration", samples),
      plugins::metric_entry("curriculum/z_m", "m", "bar height (obstacle width) z after the iteration (Table 3.1)", samples),
      plugins::metric_entry("curriculum/control_hz", "Hz", "the copies' control rate f_control(ρ(z))", samples),
      plugins::metric_entry("eval/success_rate", "",
                            "test jumps at the current z that land on the block (the first deterministic)", samples_rate),
      plugins::metric_entry("eval/return", "", "mean reward of the test jumps (eq. 3.16 × naturalness × novelty)", samples),
      plugins::metric_entry("eval/up_angle_rad", "rad", "the deterministic test jump's up-angle at the bar", samples),
      plugins::metric_entry("eval/mean_offset_l1", "rad",
                            "mean L1 norm of the P-VAE offsets in the test jumps (0 with plain targets)", samples),
      plugins::metric_entry("eval/success_rate_start_bar", "",
                            "the final policy's evaluation jumps at the starting bar (the task's bar: at least half)",
                            final_rate),
      plugins::metric_entry("eval/success_rate_final", "", "the final policy's evaluation jumps at the z reached", final_rate)};
  for (const Json& m : character::time_metric_entries()) metrics.push_back(m);  // the training's wall times
  return metrics;
}

Json runup_metrics() {
  const plugins::MetricShape samples{.x = {"samples", ""}}, rate{.x = {"samples", ""}, .rate = true};
  const plugins::MetricShape final_value{.x = {"samples", ""}, .evaluation = true},
      final_rate{.x = {"samples", ""}, .evaluation = true, .rate = true};
  Json m = {
      plugins::metric_entry("runup/return", "",
                            "mean return of the test run-ups from the reference's first frame (the first deterministic)",
                            samples),
      plugins::metric_entry("runup/handover_rate", "", "test run-ups that reached the take-off condition", rate),
      plugins::metric_entry("runup/task_reward", "", "mean r_G (eq. 3.13 high jump, 3.14 obstacle) at the hand-over", samples),
      plugins::metric_entry("runup/omega_error_x", "rad/s", "mean |ω_x − ω̄_x| at the hand-over, heading frame", samples),
      plugins::metric_entry("runup/omega_error_y", "rad/s", "mean |ω_y − ω̄_y| at the hand-over, heading frame", samples),
      plugins::metric_entry("runup/omega_error_z", "rad/s", "mean |ω_z − ω̄_z| at the hand-over, heading frame", samples),
      plugins::metric_entry("runup/lateral_speed_error", "m/s", "mean |v_y − v̄_y| at the hand-over (high jump; the thesis's v_z)",
                            samples),
      plugins::metric_entry("runup/final_task_reward", "", "the exported policy's mean r_G over final_jumps run-ups",
                            final_value),
      plugins::metric_entry("runup/final_handover_rate", "", "the exported policy's hand-over rate over final_jumps run-ups",
                            final_rate),
      plugins::metric_entry("full_jump/success_rate", "", "full jumps (run-up, then the input's jump policy) that clear the bar",
                            final_rate)};
  for (const Json& t : character::time_metric_entries()) m.push_back(t);
  return m;
}

Json feature(const char* name, double low, double high, const char* description) {
  return {{"name", name}, {"low", low}, {"high", high}, {"metric", "euclidean"}, {"unit", "rad"}, {"description", description}};
}

// A jump trial as a table (plugins/task.h "Result tables"): its bar, the share of its evaluation
// jumps that cleared it, its feature and the nearest captured technique (when labelled).
Json jump_table(const std::string& bar, double bar_m, const std::string& success, double success_rate, double up_angle_rad,
                const Json& info) {
  const Json technique = info.contains("nearest_technique") ? info["nearest_technique"]["name"] : Json(nullptr);
  return plugins::result_table(
      "jump",
      Json::array({plugins::table_column(bar, "m"), plugins::table_column(success), plugins::table_column("up-angle", "rad"),
                   plugins::table_column("nearest captured technique")}),
      Json::array(
          {Json::array({bar_m, success_rate, std::isnan(up_angle_rad) ? Json(nullptr) : Json(up_angle_rad), technique})}));
}

Json describe_stage(const TaskConfig& c) {
  if (c.stage == "pose_vae")
    return {
        {"params", Json::array()},
        {"features", Json::array()},
        {"objectives", {"fit"}},
        {"objective_info",
         Json::array({plugins::objective_entry("fit", "rad", "minus the P-VAE's reconstruction RMSE over the training poses")})},
        {"metrics",
         {plugins::metric_entry("pose_vae_loss", "", "mean P-VAE loss (MSE + β·KL) per epoch",
                                plugins::MetricShape{.x = {"epochs", ""}}),
          plugins::metric_entry("pose_vae_rmse_rad", "rad", "reconstruction RMSE over the training poses at the last epoch",
                                plugins::MetricShape{.x = {"epochs", ""}, .evaluation = true})}}};
  if (c.stage == "runup") {  // each trial's target is its input's take-off; no strategy feature of its own
    Json d = {{"params", Json::array()}, {"features", Json::array()}, {"metrics", runup_metrics()}};
    plugins::set_objectives(
        d, Json::array(
               {plugins::objective_entry("task_reward", "",
                                         "mean r_G (eq. 3.13 high jump, 3.14 obstacle) of the exported run-up at the hand-over"),
                plugins::objective_entry("full_jump_success_rate", "",
                                         "full jumps (run-up, then the input's jump policy) that clear the bar")}));
    return d;
  }
  Json params = Json::array();
  for (const TakeoffFeature& f : c.box) params.push_back({{"name", f.name}, {"low", f.low}, {"high", f.high}});
  Json d = {{"params", params}, {"metrics", metrics()}};
  plugins::set_objectives(
      d, Json::array({plugins::objective_entry("z_reached_m", "m", "the bar height (obstacle width) the curriculum reached"),
                      plugins::objective_entry("success_rate_start_bar", "",
                                               "the final policy's evaluation jumps that clear the starting bar")}));
  constexpr double pi = std::numbers::pi;
  if (c.stage == "evaluate") {
    d["params"] = Json::array();  // each trial's take-off state is its shipped entry's
    plugins::set_objectives(
        d,
        Json::array({plugins::objective_entry("success_rate", "", "the shipped policy's evaluation jumps that clear its bar")}));
  }
  if (c.stage == "explore" || c.stage == "evaluate") {
    d["features"] = {feature("up_angle_rad", 0.0, pi,
                             "angle between the root's forward axis and up as the COM crosses the bar's plane (0: facing up, a "
                             "flop; π/2: a scissor; π: facing down, a straddle)")};
  } else {
    d["features"] = {
        feature("rotation_x", -pi, pi, "the root orientation at the bar in the bar frame as a rotation vector: its x component"),
        feature("rotation_y", -pi, pi, "the root orientation at the bar in the bar frame as a rotation vector: its y component"),
        feature("rotation_z", -pi, pi, "the root orientation at the bar in the bar frame as a rotation vector: its z component")};
  }
  d["strategy_threshold"] = kUpAngleStrategyThresholdRad;  // strategy_feature.h says why (Stage 2: the same radians)
  // A trained jump is a strategy only if its deterministic test jump clears the starting bar
  // (§3.6.1's success); one that does not has a feature but no strategy, and hands nothing over.
  if (c.stage == "explore" || c.stage == "novel") d["success"] = {{"info", "/start_bar/deterministic_success"}};
  return d;
}

std::vector<double> takeoff_params(const TaskConfig& c, const Json& params) {
  std::vector<double> x;
  for (const TakeoffFeature& f : c.box) {
    if (!params.contains(f.name) || !params[f.name].is_number())
      throw base::UserError("jump " + c.stage + ": params." + f.name + " is missing or not a number (got " + params.dump() + ")");
    x.push_back(params[f.name].get<double>());
  }
  return x;
}

// Stage 2's hand-over: the Stage 1 trial's policy and its 3-D feature, and the features the
// novel-policy search found since (its context).
TrialInputs novel_inputs(const plugins::RunRequest& request) {
  if (request.inputs.size() != 1)
    throw base::UserError(
        "jump novel: needs exactly one input trial from an explore stage (inputs with \"per_trial\": \"each\"), got " +
        std::to_string(request.inputs.size()));
  const plugins::InputTrial& in = request.inputs.front();
  const std::string name = in.stage + "/" + std::to_string(in.trial_index);
  if (!in.artifacts.count("policy"))
    throw base::UserError("jump novel: input trial " + name + " has no artifact policy (is it a jump trial?)");
  const Json rotation = in.info.value("bar_frame_rotation", Json());
  if (!rotation.is_array() || rotation.size() != 3)
    throw base::UserError("jump novel: input trial " + name +
                          " has no info.bar_frame_rotation of 3 values (is it a jump trial?)");
  TrialInputs inputs;
  if (in.artifacts.count("pose_vae")) {  // the P-VAE its Stage 1 trial acted through
    inputs.prior_file = in.artifacts.at("pose_vae");
    inputs.prior = load_pose_prior(inputs.prior_file);
  }
  const Json warm = request.context.value("warm_start", Json());
  inputs.warm_start = warm.is_string() ? warm.get<std::string>() : in.artifacts.at("policy").string();
  inputs.known.push_back(rotation.get<std::vector<double>>());
  const Json found =
      request.context.contains("novelty") ? request.context["novelty"].value("features", Json::array()) : Json::array();
  for (const auto& f : found)
    if (f.is_array() && f.size() == 3) inputs.known.push_back(f.get<std::vector<double>>());
  return inputs;
}

// Stage 1's optional hand-over: the campaign's P-VAE (a pose_vae trial's `pose_vae` artifact).
TrialInputs explore_inputs(const plugins::RunRequest& request) {
  TrialInputs inputs;
  if (request.inputs.empty()) return inputs;  // plain PD targets
  const plugins::InputTrial& in = request.inputs.front();
  if (request.inputs.size() != 1 || !in.artifacts.count("pose_vae"))
    throw base::UserError("jump explore: takes at most one input trial, a pose_vae trial (its artifact pose_vae), got " +
                          std::to_string(request.inputs.size()) + " from stage " + in.stage);
  inputs.prior_file = in.artifacts.at("pose_vae");
  inputs.prior = load_pose_prior(inputs.prior_file);
  return inputs;
}

// What the dashboard's strategy gallery shows beside a trial's motion: `summary`, and the nearest
// captured technique to a Stage 1 feature when the captures' folder is configured (also in info).
Json labelled(const TaskConfig& c, Json summary, double up_angle_rad, Json& info) {
  if (!c.captured_motions.empty()) {
    const auto techniques = captured_techniques(c.captured_motions, sim::load_shipped_model(c.train.env.model));
    const CapturedTechnique& nearest = nearest_technique(techniques, up_angle_rad);
    summary["nearest captured technique"] = nearest.name;
    info["nearest_technique"] = {{"name", nearest.name}, {"up_angle_rad", nearest.up_angle_rad}};
  }
  return summary;
}

plugins::RunResult run_shipped(const TaskConfig& c, const plugins::RunRequest& request) {
  if (c.shipped.empty() || !request.inputs.empty())
    throw base::UserError("jump evaluate: needs `shipped` policies and no input trials");
  const ShippedJump& entry = c.shipped[request.trial_index % c.shipped.size()];
  EvaluationJumps jumps = c.train.eval;
  jumps.jumps = c.train.final_jumps;
  const JumpEvaluation e = evaluate_shipped(entry, c.train.env, jumps, request.work_dir / "rollouts");
  plugins::RunResult result;
  result.objectives = {e.success_rate};
  result.features = {e.up_angle_rad};
  if (!e.trajectory.empty()) result.artifacts = {{"trajectory", e.trajectory}};
  result.info = {{"success_rate", e.success_rate}, {"up_angle_rad", e.up_angle_rad}, {"policy", entry.policy}};
  result.info["summary"] =
      labelled(c, {{"bar m", entry.z_m}, {"success over " + std::to_string(jumps.jumps) + " jumps", e.success_rate}},
               e.up_angle_rad, result.info);
  result.info["table"] = jump_table("bar", entry.z_m, "success over " + std::to_string(jumps.jumps) + " jumps", e.success_rate,
                                    e.up_angle_rad, result.info);
  return result;
}

plugins::RunResult run_pose_vae(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  const PoseVaeOutcome out =
      train_pose_prior(c.pose, request.work_dir, request.seed, request.cancel,
                       {[&sink](double fraction) { sink.progress(fraction); },
                        [&sink](const std::string& name, double step, double value) { sink.metric(name, step, value); }});
  if (out.file.empty()) throw std::runtime_error("jump pose_vae: cancelled");
  plugins::RunResult result;
  result.objectives = {-out.rmse_rad};
  result.artifacts = {{"pose_vae", out.file}};
  result.info = {{"poses", out.poses},
                 {"rmse_rad", out.rmse_rad},
                 {"summary", {{"poses", out.poses}, {"reconstruction RMSE rad", out.rmse_rad}}}};
  return result;
}

// The runup stage: the target is the input trial's take-off (its params; without an input, the
// config's takeoff_features), and with its policy the full jump is recorded and measured.
plugins::RunResult run_runup(TaskConfig c, const plugins::RunRequest& request, plugins::Sink& sink) {
  if (request.inputs.size() > 1)
    throw base::UserError("jump runup: takes at most one input trial (inputs with \"per_trial\": \"each\"), got " +
                          std::to_string(request.inputs.size()));
  std::optional<JumpPolicy> jump;
  if (request.inputs.empty() && !c.shipped.empty()) {  // a shipped strategy (trial i: entry i mod n), as the evaluate stage
    const ShippedJump& entry = c.shipped[request.trial_index % c.shipped.size()];
    c.train.env.takeoff_features = entry.takeoff;
    c.train.env.difficulty_m = entry.z_m;
    jump = JumpPolicy{entry.policy, {}, c.train.env};
    if (!entry.pose_vae.empty()) jump->prior = load_pose_prior(entry.pose_vae);
  }
  if (!request.inputs.empty()) {
    const plugins::InputTrial& in = request.inputs.front();
    c.train.env.takeoff_features = takeoff_params(c, in.params);
    if (!in.artifacts.count("policy"))
      throw base::UserError("jump runup: input trial " + in.stage + "/" + std::to_string(in.trial_index) +
                            " has no artifact policy");
    jump = JumpPolicy{in.artifacts.at("policy"), {}, c.train.env};
    if (in.artifacts.count("pose_vae")) jump->prior = load_pose_prior(in.artifacts.at("pose_vae"));
  }
  if (c.train.env.takeoff_features.empty())
    throw base::UserError(
        "jump runup: no target take-off: give an input trial of an explore or novel stage, or takeoff_features");
  c.runup.takeoff_features = c.train.env.takeoff_features;
  const RunupOutcome out =
      run_runup_trial(c.train, c.runup, jump, {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});
  plugins::RunResult result;
  result.objectives = {out.runups.task_reward, out.full.success_rate};
  result.artifacts = {{"policy", out.policy}};
  if (!out.full.trajectory.empty()) result.artifacts.push_back({"trajectory", out.full.trajectory});
  result.info = out.to_json();
  result.info["summary"] = {{"run-up r_G", out.runups.task_reward},
                            {"hand-over rate", out.runups.handover_rate},
                            {"full jump success", out.full.success_rate}};
  return result;
}

}  // namespace

class JumpTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const TaskConfig c = config_from(config);
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_task_config(r); });
    Json d = describe_stage(c);
    d["presets"] = presets();
    d["config"] = accepted;
    d["config_defaults"] = base::ConfigReader::defaults(accepted);
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    TaskConfig c = config_from(request.config);
    if (c.stage == "pose_vae") return run_pose_vae(c, request, sink);
    if (c.stage == "evaluate") return run_shipped(c, request);
    if (c.stage == "runup") return run_runup(c, request, sink);
    TrialInputs inputs;
    if (c.stage == "novel") {
      inputs = novel_inputs(request);
      if (request.context.contains("novelty") && request.context["novelty"].contains("d_threshold"))
        c.train.env.novelty_threshold_rad = request.context["novelty"]["d_threshold"].get<double>();
    } else {
      inputs = explore_inputs(request);
    }
    c.train.env.takeoff_features = takeoff_params(c, request.params);
    const JumpOutcome out =
        run_jump_trial(c.train, inputs, {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});

    plugins::RunResult result;
    result.objectives = {out.z_reached_m, out.start_bar.success_rate};
    const JumpEvaluation& shown = out.shown();
    if (c.stage == "explore") result.features = {shown.up_angle_rad};
    else result.features = {shown.bar_rotation(0), shown.bar_rotation(1), shown.bar_rotation(2)};
    result.artifacts = {{"policy", out.policy}, {"trajectory", shown.trajectory}};
    if (inputs.prior.vae) {  // handed on: Stage 2 acts through the same P-VAE as its Stage 1 trial
      const auto copy = request.work_dir / "pose_vae.pt";
      std::filesystem::copy_file(inputs.prior_file, copy, std::filesystem::copy_options::overwrite_existing);
      result.artifacts.push_back({"pose_vae", copy});
    }
    result.info = out.to_json();
    const Json summary = {{"bar reached m", out.z_reached_m}, {"success at the starting bar", out.start_bar.success_rate}};
    result.info["summary"] = c.stage == "explore" ? labelled(c, summary, shown.up_angle_rad, result.info)
                                                  : summary;  // Stage 2's feature is 3-D: not labelled
    result.info["table"] = jump_table("bar reached", out.z_reached_m, "success at the starting bar", out.start_bar.success_rate,
                                      c.stage == "explore" ? shown.up_angle_rad : std::nan(""), result.info);
    return result;
  }
};

}  // namespace podium::tasks::jump

PODIUM_EXPORT_TASK(podium::tasks::jump::JumpTask, "jump")
