// The get-up task plugin (issue 18; get-up seed 001): the Discover and Weaker stages as one trial
// (discover_weaker.h). README.md gives the question, the metrics and the presets.

#include "discover_weaker.h"
#include "podium/plugins/export.h"

namespace podium::tasks::getup {

using base::Json;

namespace {

Settings settings_from(const Json& config) {
  base::ConfigReader r(config, "", "getup config");
  Settings s = read_settings(r);
  r.finish();
  return s;
}

Json accepted_config() { return base::ConfigReader::describe([](base::ConfigReader& r) { read_settings(r); }); }

// smoke: seconds (short episodes, tiny networks, ω below any return so the curriculum advances at
// every test); quick: this machine (the issue-18 probe's 256-256 networks and batch 256 at a
// fractional update ratio; not yet measured to reach the bars); paper: Table 1 and App. D.
Json presets() {
  return {{"smoke",
           {{"episode_steps", 50}, {"fall_steps", 20}, {"total_steps", 400}, {"eval_every", 100}, {"eval_starts", 2},
            {"threshold", -1.0}, {"min_steps", 100}, {"max_steps", 200}, {"checkpoint_every", 1}, {"sac_preset", "quick"},
            {"sac", {{"hidden", {16, 16}}, {"batch_size", 32}, {"warmup_steps", 100}, {"buffer_capacity", 10000}}}}},
          {"quick",
           {{"total_steps", 1'200'000}, {"sac_preset", "paper"},
            {"sac", {{"hidden", {256, 256}}, {"batch_size", 256}, {"updates_per_step", 0.25}}}}},
          {"paper", {{"total_steps", 10'000'000}, {"sac_preset", "paper"}, {"sac", Json::object()}}}};
}

}  // namespace

class GetupTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    settings_from(config);
    const Json accepted = accepted_config();
    const auto metric = [](const char* name, const char* unit, const char* text) {
      Json m = {{"name", name}, {"description", text}};
      if (*unit) m["unit"] = unit;
      return m;
    };
    return {{"params", Json::array()},  // the seed finds different get-ups from different seeds (§4)
            {"features", Json::array()},
            {"metrics",
             {metric("test_return", "", "mean R_weak return on the fixed starts at β^i; step = environment steps"),
              metric("head_height_m", "m", "mean head-top height at the end of the test episodes"),
              metric("success_rate", "", "fraction of the fixed starts ending with the head top above success_height_m"),
              metric("curriculum/strength", "", "β^i, the torque multiplier trained at after the test"),
              metric("train_return", "", "mean return of the training episodes since the last test"),
              metric("sac/alpha", "", "SAC's temperature α")}},
            {"objectives", {"success_rate", "weakness"}},  // of the exported policy; weakness = 1 − its β^i
            {"presets", presets()},
            {"config", accepted},
            {"config_defaults", base::ConfigReader::defaults(accepted)}};
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const Settings s = settings_from(request.config);
    const Reporter reporter{[&](const std::string& name, double step, double value) { sink.metric(name, step, value); },
                            [&](double fraction) { sink.progress(fraction); }};
    const TrialOutcome out = run_discover_weaker(s, request.seed, request.work_dir, request.cancel, reporter);
    plugins::RunResult result;
    result.objectives = {out.success_rate, 1.0 - out.policy_strength};
    result.artifacts = {{"policy", out.policy}, {"trajectory", out.trajectory}};
    result.info = out.to_json();
    return result;
  }
};

}  // namespace podium::tasks::getup

PODIUM_EXPORT_TASK(podium::tasks::getup::GetupTask, "getup")
