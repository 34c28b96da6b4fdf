// The get-up task plugin (get-up seed 001). One plugin, three stages chosen by the
// config key `stage`: "weaker" (Discover + Weaker, discover_weaker.h), "slower" (slower.h, once
// per Weaker policy) and "evaluate" (evaluate.h, once per Slower policy). README.md gives the
// question, the metrics and the presets.

#include <cmath>
#include <cstdio>
#include <map>

#include "evaluate.h"
#include "podium/plugins/export.h"

namespace podium::tasks::getup {

using base::Json;

namespace {

// A policy pair used without an input trial: the demo's shipped policies for Evaluate, or a
// π_weak file for Slower to imitate.
struct ShippedPolicy {
  std::filesystem::path weak_policy;  // π_weak's TorchScript export
  double weak_strength = 1.0;         // the β it passed at
  std::filesystem::path slow_policy;  // π_slow's; empty: fast runs only
};

struct TaskConfig {
  std::string stage = "weaker";
  Settings settings;
  SlowerConfig slower;
  EvaluateConfig evaluate;
  // Without an input trial, a Slower or Evaluate trial i takes shipped[i mod n] (paths relative
  // to the directory `podium run` starts in).
  std::vector<ShippedPolicy> shipped;
};

TaskConfig read_task_config(base::ConfigReader& r) {
  TaskConfig c;
  c.stage =
      r.choice("stage", c.stage, {"weaker", "slower", "evaluate"},
               "weaker: Discover + Weaker (Algorithm 1); slower: imitation of π_weak retimed (Algorithm 2), one input "
               "from a weaker stage or a `shipped` π_weak; evaluate: unseen falls at several speeds, one input from a slower "
               "stage or `shipped` policies");
  c.settings = read_settings(r);
  c.slower = read_slower(r);
  c.evaluate = read_evaluate(r);
  c.shipped = r.objects(
      "shipped",
      [](base::ConfigReader& p) {
        ShippedPolicy s;
        s.weak_policy = p.file("weak_policy", base::required, "π_weak's TorchScript file");
        s.weak_strength =
            p.number("weak_strength", base::required, {.min = 0.0, .max = 1.0, .exclusive_min = true}, "the β π_weak passed at");
        s.slow_policy = p.file("slow_policy", "", "π_slow's TorchScript file (none: fast runs only)");
        return s;
      },
      "Slower or Evaluate without an input trial: trial i takes entry i mod n (Slower imitates its weak_policy; paths "
      "relative to the spec file's folder)");
  // Slower trains π_slow: a shipped one would be ignored, so it is refused.
  if (c.stage == "slower")
    for (std::size_t i = 0; i < c.shipped.size(); ++i)
      if (!c.shipped[i].slow_policy.empty())
        r.fail("shipped",
               "entry " + std::to_string(i) + " has a slow_policy, but a slower stage trains π_slow (give weak_policy alone)");
  return c;
}

TaskConfig config_from(const Json& config) { return base::ConfigReader::parse(config, "getup config", read_task_config); }

Json accepted_config() {
  return base::ConfigReader::describe([](base::ConfigReader& r) { read_task_config(r); });
}

// smoke: seconds (short episodes, tiny networks, ω below any return so the curriculum advances at
// every test; Slower's τ_fast end at 0.01 m ends τ_fast at its first steps, so the smoke campaign
// checks the stages' mechanics, not a get-up). quick: 2 cores (RESULTS.md); its wall-clock
// limits keep the campaign inside the task's 2 h bar on machines of any speed (Weaker 100 min, Slower
// 12, Evaluate under a minute), the step counts bind on machines fast enough. paper: Table 1 and
// App. D. Every preset runs the seed repository's body (EnvSettings: humanoid21_seed, its passive
// joints, π_weak at 200 Hz, π_slow at 800 Hz) and its Slower targets (SlowerSettings); docs/tasks/getup.md
// tabulates each setting against the seed's code.
Json presets() {
  return {{"smoke",
           {{"episode_steps", 50},
            {"fall_steps", 20},
            {"total_steps", 400},
            {"eval_every", 100},
            {"eval_starts", 2},
            {"threshold", -1.0},
            {"min_steps", 100},
            {"max_steps", 200},
            {"checkpoint_every", 1},
            {"sac_preset", "quick"},
            {"sac", {{"hidden", {16, 16}}, {"batch_size", 32}, {"warmup_steps", 100}, {"buffer_capacity", 10000}}},
            {"rise_height_m", 0.1},
            {"reference_end_height_m", 0.01},
            {"max_rise_steps", 50},
            {"balance_steps", 10},
            {"slow_total_steps", 200},
            {"slow_eval_every", 100},
            {"eval_falls", 2},
            {"eval_kappas", {0.5}},
            {"pause_steps", 2},
            {"stand_steps", 5}}},
          {"quick",
           {{"total_steps", 2'000'000},
            {"train_minutes", 100},
            {"sac_preset", "paper"},
            {"sac",
             {{"hidden", {128, 128}}, {"batch_size", 256}, {"updates_per_step", 0.5}, {"actor_lr", 3e-4}, {"critic_lr", 3e-4}}},
            {"slow_total_steps", 200'000},
            {"slow_train_minutes", 12}}},
          {"paper",
           {{"total_steps", 10'000'000}, {"sac_preset", "paper"}, {"sac", Json::object()}, {"slow_total_steps", 2'000'000}}}};
}

// The strategy features (strategy_features.h) with what each means.
Json described_features() {
  const std::map<std::string, std::string> meaning = {
      {"chest_up_at_half_height",
       "torso front axis z when the head top first passes half the rise height (+1: rising from the back, −1: from the front)"},
      {"side_lean", "mean torso left axis z over the rise (+: turning over the right side, −: over the left)"},
      {"hand_support", "fraction of the rise with a hand or forearm on the ground"},
      {"knee_support", "fraction of the rise with a shin on the ground (kneeling)"}};
  Json features = StrategyFeatures::describe();
  for (Json& f : features)
    if (const auto it = meaning.find(f["name"].get<std::string>()); it != meaning.end()) f["description"] = it->second;
  return features;
}

Json stage_description(const std::string& stage) {
  // The metrics' plots: training curves over environment steps; the evaluation's points over κ
  // (1 = fast: π_weak itself) or over π_weak's strength β.
  const plugins::MetricShape steps{.x = {"environment steps", ""}}, steps_rate{.x = {"environment steps", ""}, .rate = true};
  const plugins::MetricShape kappa{.x = {"κ", ""}, .evaluation = true},
      kappa_rate{.x = {"κ", ""}, .evaluation = true, .rate = true};
  const plugins::MetricShape strength_rate{.x = {"strength β", ""}, .evaluation = true, .rate = true};
  if (stage == "slower")
    return {
        {"features", Json::array()},
        {"metrics",
         {plugins::metric_entry("slow/test_return", "", "mean return of π_slow on the fixed starts at slow_test_kappa", steps),
          plugins::metric_entry("slow/com_error_m", "m",
                                "mean |h_com − h'_com| over the tracked part of the rise on those starts", steps),
          plugins::metric_entry("slow/tracked_fraction", "",
                                "mean share of the rise tracked before a 0.5 m COM deviation ended the episode", steps_rate),
          plugins::metric_entry("slow/end_com_gap_m", "m",
                                "mean h'_com − h_com at the last rise step reached (positive: below the reference)", steps),
          plugins::metric_entry("slow/success_rate", "", "fraction of those starts standing at the end", steps_rate)}},
        {"objectives", {"success_rate", "neg_com_error_m"}},
        {"objective_info",
         Json::array({plugins::objective_entry("success_rate", "",
                                               "fraction of the fixed starts π_slow stands at the end of, at slow_test_kappa"),
                      plugins::objective_entry("neg_com_error_m", "m",
                                               "minus π_slow's mean COM-height tracking error on those starts")})}};
  const Json features = {{"features", described_features()}, {"strategy_threshold", 0.3}};
  if (stage == "evaluate") {
    Json d = features;
    d["metrics"] = {
        plugins::metric_entry("eval/success_rate", "", "success over the unseen falls (κ = 1: fast, π_weak itself)", kappa_rate),
        plugins::metric_entry("eval/rise_time_s", "s", "mean time from the fall's end to the head top above rise_height_m",
                              kappa),
        plugins::metric_entry("eval/stood_rate", "",
                              "fraction of the unseen falls whose head top stayed above rise_height_m for the last stand_steps",
                              kappa_rate),
        plugins::metric_entry(
            "eval/head_drops", "",
            "mean times the head top fell back below rise_height_m, over the falls that rose (standing: 0; a leap loop: 2–4)",
            kappa),
        plugins::metric_entry("eval/com_error_m", "m",
                              "mean COM-height tracking error of π_slow over the tracked part of the rise", kappa),
        plugins::metric_entry("eval/tracked_fraction", "",
                              "mean share of the rise π_slow tracked before a 0.5 m COM deviation ended it", kappa_rate),
        plugins::metric_entry("eval/end_com_gap_m", "m",
                              "mean h'_com − h_com at the last rise step π_slow reached (positive: below the reference)", kappa),
        plugins::metric_entry("eval/strength_success_rate", "", "π_weak's success over the unseen falls", strength_rate)};
    plugins::set_objectives(
        d, Json::array({plugins::objective_entry("slow_success_rate", "",
                                                 "mean slowed success: π_slow's success over the unseen falls, averaged over the "
                                                 "speeds κ < 1 (π_weak's fast success when there is no π_slow)"),
                        plugins::objective_entry("fast_success_rate", "",
                                                 "fast success: π_weak's success over the unseen falls at its own strength")}));
    return d;
  }
  Json d = features;
  d["metrics"] = {
      plugins::metric_entry("test_return", "", "mean R_weak return on the fixed starts at β^i", steps),
      plugins::metric_entry("test_return_min", "", "the lowest of those returns: R_test, which advances β above ω (§5)", steps),
      plugins::metric_entry("head_height_m", "m", "mean head-top height at the end of the test episodes", steps),
      plugins::metric_entry("success_rate", "", "fraction of the fixed starts ending with the head top above success_height_m",
                            steps_rate),
      plugins::metric_entry("risen_rate", "",
                            "fraction of the fixed starts whose head top passed success_height_m at some step (risen − success: "
                            "rose and fell again)",
                            steps_rate),
      plugins::metric_entry(
          "risen_on_back_rate", "",
          "risen_rate over the fixed starts that lie on the back (the torso's front axis up); absent when none does", steps_rate),
      plugins::metric_entry("stood_on_back_rate", "", "stood_rate over those starts", steps_rate),
      plugins::metric_entry("stood_rate", "",
                            "fraction of the fixed starts whose head top stayed above success_height_m for the last stand_steps "
                            "control steps (a get-up that stands; a leap's flight is shorter)",
                            steps_rate),
      plugins::metric_entry("head_drops", "",
                            "mean times the head top fell back below success_height_m, over the fixed starts whose head passed "
                            "it (a get-up that stands: 0; a leap loop: 2–4 per 250 steps)",
                            steps),
      plugins::metric_entry(
          "head_peak_m", "m",
          "mean highest head top over those starts (standing humanoid21: 1.56 m; above it: the character leaps)", steps),
      plugins::metric_entry("curriculum/strength", "", "β^i, the torque multiplier trained at after the test", steps),
      plugins::metric_entry("train_return", "", "mean return of the training episodes since the last test", steps),
      plugins::metric_entry("sac/alpha", "", "SAC's temperature α", steps),
      plugins::metric_entry("sac/skipped_updates", "", "SAC updates skipped for a non-finite loss (a diverging critic), so far",
                            steps)};
  plugins::set_objectives(
      d, Json::array({plugins::objective_entry(
                          "success_rate", "",
                          "fraction of the fixed starts the exported policy gets up from, at the strength it passed at"),
                      plugins::objective_entry(
                          "weakness", "", "1 − β^i, the torque multiplier the exported policy passed at (0: full strength)")}));
  return d;
}

const plugins::InputTrial& one_input(const plugins::RunRequest& request, const std::string& stage,
                                     const std::vector<std::string>& artifacts, const std::string& info_key,
                                     const std::string& from) {
  if (request.inputs.size() != 1)
    throw base::UserError("getup " + stage + ": needs exactly one input trial from a " + from +
                          " stage (inputs with \"per_trial\": \"each\"), got " + std::to_string(request.inputs.size()));
  const plugins::InputTrial& in = request.inputs.front();
  for (const auto& a : artifacts)
    if (!in.artifacts.count(a))
      throw base::UserError("getup " + stage + ": input trial " + in.stage + "/" + std::to_string(in.trial_index) +
                            " has no artifact " + a + " (is it a " + from + " trial?)");
  if (!in.info.contains(info_key) || !in.info[info_key].is_number())
    throw base::UserError("getup " + stage + ": input trial " + in.stage + "/" + std::to_string(in.trial_index) +
                          " has no info." + info_key + " (is it a " + from + " trial?)");
  return in;
}

// The `shipped` entry a trial without input trials takes (entry i mod n); null when the trial has
// inputs or nothing is shipped.
const ShippedPolicy* shipped_for(const TaskConfig& c, const plugins::RunRequest& request) {
  if (!request.inputs.empty() || c.shipped.empty()) return nullptr;
  return &c.shipped[request.trial_index % c.shipped.size()];
}

character::StageRun stage_run(const plugins::RunRequest& request, plugins::Sink& sink) {
  return {request.seed, request.work_dir, request.cancel, character::Reporter::to(sink)};
}

}  // namespace

class GetupTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const TaskConfig c = config_from(config);
    const Json accepted = accepted_config();
    Json d = stage_description(c.stage);
    if (c.stage != "evaluate")  // the training stages' wall times (character/training_stage.h)
      for (const Json& m : character::time_metric_entries()) d["metrics"].push_back(m);
    d["params"] = Json::array();  // the seed finds different get-ups from different seeds (§4)
    d["presets"] = presets();
    d["config"] = accepted;
    d["config_defaults"] = base::ConfigReader::defaults(accepted);
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const TaskConfig c = config_from(request.config);
    if (c.stage == "slower") return run_slower_stage(c, request, sink);
    if (c.stage == "evaluate") return run_evaluate_stage(c, request, sink);
    if (!request.inputs.empty()) throw base::UserError("getup weaker: takes no input trials (it starts from scratch, §4)");
    const TrialOutcome out = run_discover_weaker(c.settings, stage_run(request, sink));
    plugins::RunResult result;
    result.objectives = {out.success_rate, 1.0 - out.policy_strength};
    result.features = out.features.as_vector();
    result.artifacts = {{"policy", out.policy}, {"trajectory", out.trajectory}};
    result.info = out.to_json();
    return result;
  }

 private:
  static plugins::RunResult run_slower_stage(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
    WeakPolicy weak;
    if (const ShippedPolicy* p = shipped_for(c, request)) {
      weak = {p->weak_policy, p->weak_strength};
    } else {
      const auto& in = one_input(request, "slower", {"policy"}, "policy_strength", "weaker");
      weak = {in.artifacts.at("policy"), in.info["policy_strength"].get<double>()};
    }
    const SlowerOutcome out = run_slower(c.settings, c.slower, weak, stage_run(request, sink));
    plugins::RunResult result;
    result.objectives = {out.success_rate, -out.com_error_m};
    result.artifacts = {{"policy", out.policy}, {"weak_policy", out.weak_policy}, {"trajectory", out.trajectory}};
    result.info = out.to_json();
    result.info["weak_strength"] = weak.strength;
    return result;
  }

  static plugins::RunResult run_evaluate_stage(const TaskConfig& c, const plugins::RunRequest& request, plugins::Sink& sink) {
    WeakPolicy weak;
    std::filesystem::path slow;
    if (const ShippedPolicy* p = shipped_for(c, request)) {
      weak = {p->weak_policy, p->weak_strength};
      slow = p->slow_policy;
    } else {
      const auto& in = one_input(request, "evaluate", {"policy", "weak_policy"}, "weak_strength", "slower");
      weak = {in.artifacts.at("weak_policy"), in.info["weak_strength"].get<double>()};
      slow = in.artifacts.at("policy");
    }
    const EvaluateOutcome out = run_evaluate(c.settings, c.slower, c.evaluate, slow, weak, request.work_dir, request.cancel);
    plugins::RunResult result;
    double slow_success = 0.0;
    int slow_speeds = 0;
    for (const auto& s : out.speeds) {
      if (s.name == "pause") continue;
      if (s.strength > 0) {  // a fast run: by strength, and π_weak's own one also as κ = 1
        sink.metric("eval/strength_success_rate", s.strength, s.success_rate);
        if (s.name != "fast") continue;
      }
      const double step = s.name == "fast" ? 1.0 : s.kappa;
      sink.metric("eval/success_rate", step, s.success_rate);
      sink.metric("eval/rise_time_s", step, s.rise_time_s);
      sink.metric("eval/head_drops", step, s.drops);
      sink.metric("eval/stood_rate", step, static_cast<double>(s.stood) / c.evaluate.falls);
      if (s.name != "fast") {
        sink.metric("eval/com_error_m", step, s.com_error_m);
        sink.metric("eval/tracked_fraction", step, s.tracked_fraction);
        sink.metric("eval/end_com_gap_m", step, s.end_com_gap_m);
        slow_success += s.success_rate, ++slow_speeds;
      }
    }
    // Without π_slow (shipped π_weak alone) the primary objective is the fast success.
    result.objectives = {slow_speeds > 0 ? slow_success / slow_speeds : out.at("fast").success_rate, out.at("fast").success_rate};
    result.features = out.features.as_vector();
    // `trajectory` (what the replay page shows) is the slow speed nearest κ = 0.5; the others
    // keep their names (trajectory_fast, trajectory_k0.25, trajectory_pause, ...).
    std::size_t shown = 0;
    for (std::size_t i = 0; i < out.speeds.size(); ++i) {
      const auto& s = out.speeds[i];
      if (s.strength == 0 && s.name != "pause" &&
          (shown == 0 || std::abs(s.kappa - 0.5) < std::abs(out.speeds[shown].kappa - 0.5)))
        shown = i;
    }
    for (std::size_t i = 0; i < out.speeds.size(); ++i)
      result.artifacts.push_back({i == shown ? "trajectory" : "trajectory_" + out.speeds[i].name, out.speeds[i].trajectory});
    result.info = out.to_json();
    result.info["table"] = evaluation_table(out, c.evaluate.falls);
    return result;
  }

  // The Evaluate trial as a table (plugins/task.h "Result tables"): per speed κ (fast: π_weak at
  // its strength β), of the unseen falls how many rose and stood, the mean rise time and COM error.
  static Json evaluation_table(const EvaluateOutcome& out, int falls) {
    Json rows = Json::array();
    for (const auto& s : out.speeds) {
      const bool fast = s.kappa == 0;
      const std::string speed = fast                ? "fast β " + format_cell(s.strength)
                                : s.name == "pause" ? "paused κ " + format_cell(s.kappa)
                                                    : "κ " + format_cell(s.kappa);
      rows.push_back(Json::array({speed, s.risen, s.stood, s.risen > 0 ? Json(s.rise_time_s) : Json(nullptr),
                                  fast ? Json(nullptr) : Json(s.com_error_m)}));
    }
    return plugins::result_table(
        "evaluation over " + std::to_string(falls) + " unseen falls",
        Json::array({plugins::table_column("speed"), plugins::table_column("rose"), plugins::table_column("stood"),
                     plugins::table_column("rise time", "s"), plugins::table_column("COM error", "m")}),
        rows);
  }

  static std::string format_cell(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
  }
};

}  // namespace podium::tasks::getup

PODIUM_EXPORT_TASK(podium::tasks::getup::GetupTask, "getup")
