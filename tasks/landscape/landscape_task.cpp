// The landscape task plugin: a cheap task for tests, orchestration demos and search benchmarks,
// with optional noise, sleep and failure injection (throw, segfault, abort, exit, hang, NaN).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "landscape_model.h"
#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/plugins/export.h"

namespace podium::tasks::landscape {

using base::Json;
using plugins::RunRequest;
using plugins::RunResult;
using plugins::Sink;

namespace {

// One injected failure rule (for reliability tests of the executor).
struct FailureRule {
  std::string mode;
  std::vector<std::uint64_t> trials;  // empty: every trial
  int attempts = 0;                   // applies to attempts 1..attempts; 0: every attempt
};

struct TaskConfig {
  LandscapeOptions landscape;
  double noise = 0.0;
  double sleep_s = 0.0;
  int metric_points = 5;
  bool artifact = false;
  std::vector<FailureRule> failures;
};

// The one definition of the config: it validates in describe() and run(), and describes itself
// (base::ConfigReader::describe) for `podium tasks` and the description's "config".
TaskConfig read_config(base::ConfigReader& r) {
  TaskConfig c;
  c.landscape.family = r.choice("family", "basins", LandscapeModel::families(), "landscape family (README.md)");
  c.landscape.dim = r.integer("dim", 3, {1, 1000}, "parameters x0..x{dim-1}, each in [0, 1]");
  c.landscape.landscape_seed = r.integer<std::uint64_t>("landscape_seed", 1, {}, "picks the landscape");
  c.landscape.regions = r.integer("regions", 6, {2, 10000}, "basins, plateau levels per feature, or Voronoi cells");
  c.landscape.fail_fraction =
      r.number("fail_fraction", 0.0, {.min = 0.0, .max = 0.9},
               "fraction of the box where trials fail the task (info.success false; they still have a feature)");
  c.noise = r.number("noise", 0.0, {.min = 0.0}, "standard deviation added to each feature value");
  c.sleep_s = r.number("sleep_s", 0.0, {.min = 0.0, .max = 1e6}, "wall time a trial takes (cancellable)");
  c.metric_points = r.integer("metric_points", 5, {0, 1000000}, "points of the \"trace\" learning curve per trial");
  c.artifact = r.boolean("artifact", false, "write result.json into the trial folder");
  c.failures = r.objects(
      "failures",
      [](base::ConfigReader& f) {
        FailureRule rule;
        rule.mode = f.choice("mode", base::required, {"throw", "segfault", "abort", "exit", "hang", "nan"});
        rule.trials = f.integers<std::uint64_t>("trials", {}, {}, "trial indices it applies to (empty: every trial)");
        rule.attempts = f.integer("attempts", 0, {.min = 0}, "applies to attempts 1..n (0: every attempt)");
        return rule;
      },
      "injected failures; the first rule that applies to an attempt decides");
  return c;
}

TaskConfig parse_config(const Json& config) { return base::ConfigReader::parse(config, "landscape config", read_config); }

// Injected failure, for reliability tests of the executor.
void fail_now(const std::string& mode) {
  if (mode == "throw") throw std::runtime_error("injected failure (throw)");
  if (mode == "segfault") std::raise(SIGSEGV);
  if (mode == "abort") std::abort();
  if (mode == "exit") std::_Exit(3);
  if (mode == "hang")
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));  // ignores cancellation on purpose
}

// The mode of the first failure rule that applies to this attempt, or "".
std::string failure_for(const std::vector<FailureRule>& rules, std::uint64_t trial, int attempt) {
  for (const auto& rule : rules) {
    if (!rule.trials.empty() && std::find(rule.trials.begin(), rule.trials.end(), trial) == rule.trials.end()) continue;
    if (rule.attempts > 0 && attempt > rule.attempts) continue;
    return rule.mode;
  }
  return "";
}

}  // namespace

class LandscapeTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const TaskConfig c = parse_config(config);
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_config(r); });
    Json params = Json::array();
    for (int i = 0; i < c.landscape.dim; ++i) params.push_back({{"name", "x" + std::to_string(i)}, {"low", 0.0}, {"high", 1.0}});
    Json features = Json::array();
    for (int f = 0; f < LandscapeModel::kFeatureDim; ++f)
      features.push_back({{"name", "f" + std::to_string(f)}, {"low", 0.0}, {"high", 1.0}, {"metric", "euclidean"}});
    Json d = {
        {"params", params},
        {"features", features},
        {"metrics",
         {plugins::metric_entry("trace", "", "a synthetic learning curve ending at the objective", {.x = {"iteration", ""}})}},
        {"objectives", {"objective"}},
        {"strategy_threshold", 0.02},  // plateau values are constant: any two strategies differ more
        {"presets",
         {{"smoke", {{"dim", 3}, {"metric_points", 5}}},
          {"quick", {{"dim", 3}, {"metric_points", 50}, {"sleep_s", 0.05}}},
          {"paper", {{"dim", 4}, {"metric_points", 200}, {"sleep_s", 1.0}}}}},
        {"config", accepted},
        {"config_defaults", base::ConfigReader::defaults(accepted)}};
    if (c.landscape.fail_fraction > 0.0) d["success"] = {{"info", "/success"}};  // failed trials have no strategy
    return d;
  }

  RunResult run(const RunRequest& request, Sink& sink) override {
    const TaskConfig c = parse_config(request.config);
    const LandscapeModel model(c.landscape);
    std::vector<double> x;
    for (int i = 0; i < model.dim(); ++i) x.push_back(request.params.at("x" + std::to_string(i)).get<double>());

    const std::string failure = failure_for(c.failures, request.trial_index, request.attempt);
    if (!failure.empty() && failure != "nan") fail_now(failure);

    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < c.sleep_s) {
      if (request.cancel && request.cancel->load()) throw std::runtime_error("cancelled");
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }

    RunResult result;
    result.objectives = {model.objective(x)};
    result.features = model.feature(x);
    base::Rng rng(request.seed);
    if (c.noise > 0.0)
      for (auto& f : result.features) f += rng.normal(0.0, c.noise);
    if (failure == "nan") result.features[0] = std::nan("");
    result.info = {{"success", model.succeeds(x)}};

    const int points = c.metric_points;
    for (int k = 0; k < points; ++k) {
      // Approaches the objective from below, like a training curve.
      const double t = points > 1 ? static_cast<double>(k) / (points - 1) : 1.0;
      sink.metric("trace", k, result.objectives[0] - (1.0 - t) * (1.0 - t));
      sink.progress(t);
    }
    if (c.artifact) {
      const auto path = request.work_dir / "result.json";
      std::ofstream(path) << Json{{"x", x}, {"feature", result.features}}.dump() << '\n';
      result.artifacts.push_back({"result", path});
    }
    return result;
  }
};

}  // namespace podium::tasks::landscape

PODIUM_EXPORT_TASK(podium::tasks::landscape::LandscapeTask, "landscape")
