// The style-curve get-up task plugin (curve get-up seed). One stage so far, chosen by the config key
// `stage`: "train" — one PPO policy follows the configured style curves from lying to standing
// (train_curves.h). The presets are data (data/presets.json); README.md gives the metrics.

#include "podium/base/json.h"
#include "podium/plugins/export.h"
#include "train_curves.h"

namespace podium::tasks::getup_curves {

using base::Json;

namespace {

struct TaskConfig {
  std::string stage = "train";
  TrainSettings train;
};

TaskConfig read_task_config(base::ConfigReader& r) {
  TaskConfig c;
  c.stage = r.choice("stage", c.stage, {"train"},
                     "train: PPO on the curve set (§5), one policy for every curve; the trial's policy, motions and "
                     "target-vs-achieved features");
  c.train = read_train_settings(r);
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
      plugins::metric_entry("test/episode_s", "s", "mean length of the test episodes (§5.3's early termination shortens them)",
                            steps),
      plugins::metric_entry("train/return", "", "mean return of the training episodes that ended since the previous test", steps),
      plugins::metric_entry("final/success_rate", "", "the exported policy's success over the test starts", final_rate),
      plugins::metric_entry("final/mean_r_task", "", "the exported policy's mean r_task over the test starts", final_value)};
  for (const Json& t : character::time_metric_entries()) m.push_back(t);
  return m;
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
  if (!request.inputs.empty()) throw base::UserError("getup_curves train: takes no input trials");
  const TrainOutcome out =
      run_curve_training(c.train, {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)});
  plugins::RunResult result;
  result.objectives = {out.final.success_rate, out.final.mean_task_reward};
  result.artifacts = {{"policy", out.policy}};
  for (std::size_t k = 0; k < out.trajectories.size(); ++k)
    result.artifacts.push_back({k == 0 ? "trajectory" : "trajectory_" + std::to_string(k), out.trajectories[k]});
  if (!out.curves.empty()) result.artifacts.push_back({"curves", out.curves});
  result.info = out.to_json();
  result.info["summary"] = {
      {"success", out.final.success_rate}, {"mean r_task", out.final.mean_task_reward}, {"episode s", out.final.mean_episode_s}};
  Json rows = Json::array();
  const auto& names = out.final.curve_success;
  for (std::size_t k = 0; k < names.size(); ++k) rows.push_back(Json::array({c.train.curves.at(k), out.final.curve_success[k]}));
  result.info["table"] =
      plugins::result_table("success per curve over " + std::to_string(c.train.test_starts) + " test starts",
                            Json::array({plugins::table_column("curve"), plugins::table_column("success")}), rows);
  return result;
}

}  // namespace

class GetupCurvesTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    config_from(config);
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_task_config(r); });
    Json d = describe_stage();
    d["presets"] = presets();
    d["config"] = accepted;
    d["config_defaults"] = base::ConfigReader::defaults(accepted);
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const TaskConfig c = config_from(request.config);
    return run_train(c, request, sink);
  }
};

}  // namespace podium::tasks::getup_curves

PODIUM_EXPORT_TASK(podium::tasks::getup_curves::GetupCurvesTask, "getup_curves")
