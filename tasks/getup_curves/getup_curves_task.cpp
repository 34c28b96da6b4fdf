// The style-curve get-up task plugin (curve get-up seed). Three stages, chosen by the config key
// `stage`: "pose_cvae" — the pose C-VAE of §3.5 (pose_cvae.h); "train" — one PPO policy follows the
// configured style curves from lying to standing (train_curves.h), acting on PD targets or, with
// actions "cvae", through a pose_cvae trial's C-VAE; "edit" — a train trial's policy on one edit of
// a base curve per trial (edit_stage.h, §4.3). The presets are data (data/presets.json);
// README.md gives the metrics.

#include "curve_edit.h"
#include "curve_tool.h"
#include "edit_stage.h"
#include "podium/base/json.h"
#include "podium/learn/frozen_policy.h"
#include "podium/plugins/export.h"
#include "pose_cvae.h"
#include "train_curves.h"

namespace podium::tasks::getup_curves {

using base::Json;

namespace {

struct TaskConfig {
  std::string stage = "train";
  TrainSettings train;
  PoseCvaeSettings cvae;
  EditSettings edit;
};

TaskConfig read_task_config(base::ConfigReader& r) {
  TaskConfig c;
  c.stage = r.choice("stage", c.stage, {"pose_cvae", "train", "edit"},
                     "pose_cvae: trains the pose C-VAE (§3.5) on pose_clips, labelled by their style features; train: PPO on "
                     "the curve set (§5), one policy for every curve (with actions \"cvae\": through one input pose_cvae "
                     "trial's C-VAE); the trial's policy, motions and target-vs-achieved features; edit: one input train "
                     "trial's policy on an edit of edit_base_curve (the trial's params), from the test starts (§4.3)");
  c.train = read_train_settings(r);
  c.cvae = read_pose_cvae_settings(r);
  read_edit_settings(r, c.edit);
  if (c.stage == "pose_cvae" && c.cvae.clips.empty()) r.fail("pose_clips", "is empty: the pose_cvae stage needs clips");
  return c;
}

TaskConfig config_from(const Json& config) { return base::ConfigReader::parse(config, "getup_curves config", read_task_config); }

// The shipped presets (data/presets.json: "smoke", "quick", "paper"; its "notes" say where each
// value comes from).
Json presets() {
  const std::string file = std::string(PODIUM_GETUP_CURVES_DATA_DIR) + "/presets.json";
  const Json all = base::read_json_file(file);
  Json out = Json::object();
  for (const char* name : {"smoke", "quick", "paper"}) {
    if (!all.contains(name) || !all[name].is_object()) throw base::UserError(file + ": " + name + ": missing or not an object");
    out[name] = all[name];
  }
  return out;
}

Json metrics() {
  const plugins::MetricShape steps{.x = {"control steps", ""}}, steps_rate{.x = {"control steps", ""}, .rate = true};
  const plugins::MetricShape final_rate{.x = {"control steps", ""}, .evaluation = true, .rate = true},
      final_value{.x = {"control steps", ""}, .evaluation = true};
  Json m = {
      plugins::metric_entry("test/return", "", "mean return (eq. 2 summed) of the deterministic policy over the test starts",
                            steps),
      plugins::metric_entry("test/success_rate", "",
                            "test episodes that ran their full T + T_stand and kept h ≥ 0.9·p_h(1) through the last second",
                            steps_rate),
      plugins::metric_entry("test/mean_r_task", "", "r_task (eq. 4) averaged over every control step of the test episodes",
                            steps_rate),
      plugins::metric_entry("test/average_return_rate", "",
                            "§6.4's average return rate: r_task summed over the test episodes, divided by their full T + "
                            "T_stand in control steps (steps cut by early termination count 0)",
                            steps_rate),
      plugins::metric_entry("test/episode_s", "s", "mean length of the test episodes (§5.3's early termination shortens them)",
                            steps),
      plugins::metric_entry("train/return", "", "mean return of the training episodes that ended since the previous test", steps),
      plugins::metric_entry("final/success_rate", "", "the exported policy's success over the test starts", final_rate),
      plugins::metric_entry("final/mean_r_task", "", "the exported policy's mean r_task over the test starts", final_value),
      plugins::metric_entry("curriculum/open_levels", "",
                            "terrain regions open to training episodes (§5.4: a point at each unlock, its step the time)",
                            steps)};
  for (const char* level : {"flat", "easy", "medium", "hard"})
    m.push_back(plugins::metric_entry(std::string("test/success_rate/") + level, "",
                                      std::string("test success with drops on the ") + level + " region (once open)",
                                      steps_rate));
  for (const Json& t : character::time_metric_entries()) m.push_back(t);
  return m;
}

Json describe_cvae_stage() {
  const plugins::MetricShape epochs{.x = {"epochs", ""}}, final_value{.x = {"epochs", ""}, .evaluation = true};
  Json d = {
      {"params", Json::array()},
      {"features", Json::array()},
      {"metrics",
       {plugins::metric_entry("pose_cvae_loss", "", "mean C-VAE loss (MSE + β·KL) per epoch", epochs),
        plugins::metric_entry("pose_cvae_rmse_rad", "rad", "reconstruction RMSE over the training poses", final_value),
        plugins::metric_entry("pose_cvae_heldout_rmse_rad", "rad", "reconstruction RMSE over the held-out frames", final_value),
        plugins::metric_entry("pose_cvae_mean_pose_rmse_rad", "rad",
                              "RMSE of the training mean pose over the held-out frames (the baseline)", final_value)}}};
  plugins::set_objectives(
      d,
      Json::array({plugins::objective_entry("heldout_fit", "rad", "minus the C-VAE's reconstruction RMSE on held-out frames")}));
  return d;
}

plugins::RunResult run_pose_cvae(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  if (!request.inputs.empty()) throw base::UserError("getup_curves pose_cvae: takes no input trials");
  const PoseCvaeOutcome out = train_pose_cvae(
      c.cvae, request.work_dir, request.seed, request.cancel,
      [&sink](const std::string& name, double step, double value) { sink.metric(name, step, value); },
      [&sink](double fraction) { sink.progress(fraction); });
  if (out.cancelled) throw std::runtime_error("getup_curves pose_cvae: cancelled");
  plugins::RunResult result;
  result.objectives = {-out.heldout_rmse_rad};
  result.artifacts = {{"pose_cvae", out.file}};
  result.info = out.to_json();
  result.info["summary"] = {{"poses", out.train_poses},
                            {"held-out RMSE rad", out.heldout_rmse_rad},
                            {"mean-pose RMSE rad", out.mean_pose_rmse_rad},
                            {"PCA components for 85%", out.pca_components_85}};
  return result;
}

Json describe_stage() {
  Json d = {{"params", Json::array()}, {"features", Json::array()}, {"metrics", metrics()}};
  plugins::set_objectives(
      d, Json::array({plugins::objective_entry("success_rate", "", "the exported policy's success over the test starts"),
                      plugins::objective_entry("mean_r_task", "",
                                               "the exported policy's r_task (eq. 4) averaged over its test episodes' steps")}));
  return d;
}

plugins::RunResult run_train(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  TrainSettings train = c.train;
  std::filesystem::path cvae_file;
  if (train.env.actions == "cvae") {  // §3.4: the policy acts through the pose_cvae stage's C-VAE
    if (request.inputs.size() != 1 || !request.inputs.front().artifacts.count("pose_cvae"))
      throw base::UserError(
          "getup_curves train: actions \"cvae\" needs exactly one input trial of a pose_cvae stage (its "
          "artifact pose_cvae), got " +
          std::to_string(request.inputs.size()) + " input trials");
    cvae_file = request.inputs.front().artifacts.at("pose_cvae");
    train.env.cvae = std::shared_ptr<const learn::PoseVae>(learn::PoseVae::from_file(cvae_file));
  } else if (!request.inputs.empty()) {
    throw base::UserError(
        "getup_curves train: takes no input trials with actions \"targets\" (\"cvae\" takes a pose_cvae trial)");
  }
  const TrainOutcome out =
      run_curve_training(train, {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});
  plugins::RunResult result;
  result.objectives = {out.final.success_rate, out.final.mean_task_reward};
  result.artifacts = {{"policy", out.policy}};
  if (!cvae_file.empty()) {  // handed on with the policy that acts through it
    const auto copy = request.work_dir / "pose_cvae.pt";
    std::filesystem::copy_file(cvae_file, copy, std::filesystem::copy_options::overwrite_existing);
    result.artifacts.push_back({"pose_cvae", copy});
  }
  for (std::size_t k = 0; k < out.trajectories.size(); ++k)
    result.artifacts.push_back({recorded_trajectory_name(k), out.trajectories[k]});
  if (!out.curves.empty()) result.artifacts.push_back({"curves", out.curves});
  result.info = out.to_json();
  // How the policy acts, for the stages that run it (edit): its observation and action sizes follow.
  result.info["action_space"] = {
      {"actions", train.env.actions}, {"latent_bound", train.env.latent_bound}, {"offset_bound", train.env.offset_bound}};
  result.info["summary"] = {
      {"success", out.final.success_rate}, {"mean r_task", out.final.mean_task_reward}, {"episode s", out.final.mean_episode_s}};
  Json rows = Json::array();
  for (const CurveFollowing& f : out.final.following) {
    const Json j = f.to_json();
    rows.push_back(Json::array({f.curve, f.success_rate, j["h_error_m"], j["angle_error_deg"], j["rise_time_s"], f.risen}));
  }
  result.info["table"] = plugins::result_table(
      "per curve over " + std::to_string(c.train.final_starts > 0 ? c.train.final_starts : c.train.test_starts) +
          " test starts (errors over [0, T] of the successful ones)",
      Json::array({plugins::table_column("curve"), plugins::table_column("success"), plugins::table_column("h error", "m"),
                   plugins::table_column("angle error", "°"), plugins::table_column("rise time", "s"),
                   plugins::table_column("risen")}),
      rows);
  return result;
}

Json describe_edit_stage() {
  Json d = {{"params", edit_params()},
            {"features", edit_features()},
            {"strategy_threshold", kEditStrategyThreshold},
            {"metrics", Json::array()}};
  plugins::set_objectives(
      d, Json::array({plugins::objective_entry("success_rate", "", "the policy's success on the edited curve over the starts"),
                      plugins::objective_entry("mean_r_task", "", "its r_task (eq. 4) averaged over the episodes' steps")}));
  return d;
}

double edit_param(const plugins::RunRequest& request, const std::string& name) {
  const Json& p = request.params;
  if (!p.contains(name) || !p.at(name).is_number())
    throw base::UserError("getup_curves edit: params." + name + ": " + (p.contains(name) ? p.at(name).dump() : "missing") +
                          " is not a number");
  return p.at(name).get<double>();
}

// The edit stage's policy and action space: the shipped one when no input trial is given.
plugins::InputTrial edit_input(const TaskConfig& c, const plugins::RunRequest& request) {
  if (request.inputs.empty() && !c.edit.shipped_policy.empty()) {
    plugins::InputTrial shipped;
    shipped.stage = "shipped";
    shipped.artifacts["policy"] = c.edit.shipped_policy;
    if (!c.edit.shipped_cvae.empty()) shipped.artifacts["pose_cvae"] = c.edit.shipped_cvae;
    return shipped;
  }
  if (request.inputs.size() != 1 || !request.inputs.front().artifacts.count("policy"))
    throw base::UserError(
        "getup_curves edit: needs exactly one input train trial (its artifact policy) or edit_shipped_policy, got " +
        std::to_string(request.inputs.size()) + " input trials");
  return request.inputs.front();
}

// The edit stage: one input train trial (its policy, and its C-VAE when it acts through one), or a
// shipped policy.
plugins::RunResult run_edit(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
  const plugins::InputTrial in = edit_input(c, request);
  TrainSettings train = c.train;
  if (in.info.contains("action_space")) {  // the policy acts as it was trained to, whatever this stage's config says
    const Json& a = in.info.at("action_space");
    train.env.actions = a.at("actions").get<std::string>();
    train.env.latent_bound = a.at("latent_bound").get<double>();
    train.env.offset_bound = a.at("offset_bound").get<double>();
  } else if (in.artifacts.count("pose_cvae")) {  // a train trial hands on the C-VAE its policy acts through
    train.env.actions = "cvae";
  }
  if (train.env.actions == "cvae") {
    if (!in.artifacts.count("pose_cvae"))
      throw base::UserError("getup_curves edit: actions \"cvae\": input trial " + in.stage + "/" +
                            std::to_string(in.trial_index) + " has no artifact pose_cvae");
    train.env.cvae = std::shared_ptr<const learn::PoseVae>(learn::PoseVae::from_file(in.artifacts.at("pose_cvae")));
  }
  const learn::FrozenPolicy frozen(in.artifacts.at("policy"));
  const CurveEdit edit{edit_param(request, "rise_fraction"), edit_param(request, "h_offset_m"),
                       edit_param(request, "duration_scale")};
  const EditOutcome out = run_curve_edit(
      train, c.edit, edit, [&](std::span<const double> o, std::span<double> a) { frozen.act(o, a); }, request.work_dir);
  sink.progress(1.0);
  plugins::RunResult result;
  result.objectives = {out.test.success_rate, out.test.mean_task_reward};
  result.features = out.features;
  result.artifacts = {{"edited_curve", out.curve_file}, {"curves", out.curves}, {"trajectory", out.trajectory}};
  const CurveFollowing& f = out.test.following.at(0);
  result.info = f.to_json();
  result.info["mean_r_task"] = out.test.mean_task_reward;
  result.info["curve_rise_time_s"] = rise_time_s(out.curve);  // the edited target's rise (the fit's, not the asked)
  result.info["curve_duration_s"] = out.curve.duration_s;
  result.info["average_return_rate"] = out.test.average_return_rate;
  result.info["policy"] = in.stage == "shipped" ? c.edit.shipped_policy : in.stage + "/" + std::to_string(in.trial_index);
  result.info["summary"] = {{"curve T s", out.curve.duration_s},
                            {"success", f.success_rate},
                            {"h error m", result.info["h_error_m"]},
                            {"angle error °", result.info["angle_error_deg"]},
                            {"rise time s", result.info["rise_time_s"]}};
  return result;
}

}  // namespace

class GetupCurvesTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const TaskConfig c = config_from(config);
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_task_config(r); });
    Json d = c.stage == "pose_cvae" ? describe_cvae_stage() : c.stage == "edit" ? describe_edit_stage() : describe_stage();
    d["presets"] = presets();
    d["config"] = accepted;
    d["config_defaults"] = base::ConfigReader::defaults(accepted);
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const TaskConfig c = config_from(request.config);
    if (c.stage == "edit") return run_edit(c, request, sink);
    return c.stage == "pose_cvae" ? run_pose_cvae(c, request, sink) : run_train(c, request, sink);
  }

  // `podium tool getup_curves extract|edit|stats` (curve_tool.h).
  std::vector<plugins::ToolCommand> tools() const override { return curve_tool_commands(); }
  int tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) override {
    return run_curve_tool(args, out, err);
  }
};

}  // namespace podium::tasks::getup_curves

PODIUM_EXPORT_TASK(podium::tasks::getup_curves::GetupCurvesTask, "getup_curves")
