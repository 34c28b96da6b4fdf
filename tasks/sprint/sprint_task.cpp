// The sprint task plugin (sprint seed 002, "Learn to Sprint 100 Metres"). One stage so far, chosen
// by the config key `stage`: "start" (§3.1: PPO imitating our keyframed crouch starts, from the
// blocks to the first landing; its landing states are stage 2's start set). README.md gives the
// metrics and presets.
#include "podium/plugins/export.h"
#include "train_start.h"

namespace podium::tasks::sprint {

using base::Json;

namespace {

struct TaskConfig {
  std::string stage = "start";
  StartTrainSettings start;
};

TaskConfig read_task_config(base::ConfigReader& r) {
  TaskConfig c;
  c.stage = r.choice("stage", c.stage, {"start"},
                     "start: the Start phase (§3.1), PPO on r_base + λ_i·r_imitation of our crouch starts to the first landing");
  c.start = read_start_train_settings(r);
  return c;
}

TaskConfig config_from(const Json& config) { return base::ConfigReader::parse(config, "sprint config", read_task_config); }

// smoke: seconds (16-16 networks, 4 iterations of 64 samples, 2 copies, 150 Hz simulation; the
// mechanics only, no start is learnt). quick: 2 cores (256-128, 1024 samples per iteration,
// 600 Hz until a lower rate is measured to give the same outcomes). paper: the jump's paper scale
// (4096 samples per iteration, 1024-512, the seed gives no settings), budgets for Slurm.
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
            {"checkpoint_every", 1}}},
          {"quick",
           {{"track", "quick"},
            {"ppo_preset", "paper"},
            {"ppo", {{"hidden", {256, 128}}, {"rollout_steps", 256}}},
            {"copies", 4},
            {"threads", 2},
            {"total_samples", 2'000'000},
            {"sim_hz", 600.0},
            {"eval_every", 25},
            {"eval_episodes", 8},
            {"final_episodes", 20},
            {"checkpoint_every", 10}}},
          {"paper",
           {{"track", "paper"},
            {"ppo_preset", "paper"},
            {"ppo", {{"hidden", {1024, 512}}, {"rollout_steps", 256}}},
            {"copies", 16},
            {"threads", 16},
            {"total_samples", 5000LL * 4096},
            {"sim_hz", 600.0},
            {"eval_every", 50},
            {"eval_episodes", 16},
            {"final_episodes", 100},
            {"checkpoint_every", 10}}}};
}

Json start_metrics() {
  const plugins::MetricShape samples{.x = {"samples", ""}}, rate{.x = {"samples", ""}, .rate = true};
  const plugins::MetricShape final_value{.x = {"samples", ""}, .evaluation = true},
      final_rate{.x = {"samples", ""}, .evaluation = true, .rate = true};
  Json m = {
      plugins::metric_entry("start/return", "", "mean return of the test starts (deterministic policy)", samples),
      plugins::metric_entry("start/landing_rate", "", "test starts that reached the first landing", rate),
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

}  // namespace

class SprintTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    config_from(config);  // checks it
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_task_config(r); });
    Json d = {{"params", Json::array()}, {"features", Json::array()}, {"metrics", start_metrics()}};
    plugins::set_objectives(
        d, Json::array({plugins::objective_entry("landing_rate", "", "the exported policy's starts that reach the first landing"),
                        plugins::objective_entry("minus_tracking_error_rad", "rad",
                                                 "minus its mean per-joint rotation error against the reference")}));
    d["presets"] = presets();
    d["config"] = accepted;
    d["config_defaults"] = base::ConfigReader::defaults(accepted);
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const TaskConfig c = config_from(request.config);
    return run_start(c, request, sink);
  }
};

}  // namespace podium::tasks::sprint

PODIUM_EXPORT_TASK(podium::tasks::sprint::SprintTask, "sprint")
