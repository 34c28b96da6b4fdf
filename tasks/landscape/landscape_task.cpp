// The landscape task plugin: a cheap task for tests, orchestration demos and search benchmarks,
// with optional noise, sleep and failure injection (throw, segfault, abort, exit, hang, NaN).
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "landscape_model.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/plugins/export.h"

namespace podium::tasks::landscape {

using base::Json;
using plugins::RunRequest;
using plugins::RunResult;
using plugins::Sink;

namespace {

const Json kDefaults = {
    {"family", "basins"},    // basins | plateaus | plateaus_rough | voronoi
    {"dim", 3},
    {"landscape_seed", 1},
    {"regions", 6},
    {"noise", 0.0},          // standard deviation added to each feature value
    {"sleep_s", 0.0},        // wall time a trial takes (cancellable)
    {"metric_points", 5},    // points of the "trace" learning curve per trial
    {"artifact", false},     // write result.json into the work folder
    {"failures", Json::array()}};  // [{"mode", "trials"?: [i...], "attempts"?: n}]

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
std::string failure_for(const Json& rules, std::uint64_t trial, int attempt) {
  for (const auto& rule : rules) {
    if (rule.contains("trials")) {
      bool listed = false;
      for (const auto& t : rule["trials"]) listed = listed || t.get<std::uint64_t>() == trial;
      if (!listed) continue;
    }
    if (rule.contains("attempts") && attempt > rule["attempts"].get<int>()) continue;
    return rule.at("mode").get<std::string>();
  }
  return "";
}

void validate(const Json& config) {
  for (const auto& [key, value] : config.items())
    if (!kDefaults.contains(key)) throw base::UserError("landscape config: unknown key \"" + key + "\"");
  for (const auto& rule : config.value("failures", Json::array())) {
    const std::string mode = rule.value("mode", "");
    if (mode != "throw" && mode != "segfault" && mode != "abort" && mode != "exit" && mode != "hang" && mode != "nan")
      throw base::UserError("landscape config: failures[].mode \"" + mode +
                            "\" is not one of throw, segfault, abort, exit, hang, nan");
  }
}

Json merged(const Json& config) {
  Json c = kDefaults;
  c.update(config);
  return c;
}

LandscapeOptions options_from(const Json& c) {
  LandscapeOptions o;
  o.family = c["family"].get<std::string>();
  o.dim = c["dim"].get<int>();
  o.landscape_seed = c["landscape_seed"].get<std::uint64_t>();
  o.regions = c["regions"].get<int>();
  return o;
}

}  // namespace

class LandscapeTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    validate(config);
    const Json c = merged(config);
    Json params = Json::array();
    for (int i = 0; i < c["dim"].get<int>(); ++i)
      params.push_back({{"name", "x" + std::to_string(i)}, {"low", 0.0}, {"high", 1.0}});
    Json features = Json::array();
    for (int f = 0; f < LandscapeModel::kFeatureDim; ++f)
      features.push_back({{"name", "f" + std::to_string(f)}, {"low", 0.0}, {"high", 1.0}, {"metric", "euclidean"}});
    return {{"params", params},
            {"features", features},
            {"metrics", {{{"name", "trace"}, {"description", "a synthetic learning curve ending at the objective"}}}},
            {"objectives", {"objective"}},
            {"strategy_threshold", 0.02},  // plateau values are constant: any two strategies differ more
            {"presets",
             {{"smoke", {{"dim", 3}, {"metric_points", 5}}},
              {"quick", {{"dim", 3}, {"metric_points", 50}, {"sleep_s", 0.05}}},
              {"paper", {{"dim", 4}, {"metric_points", 200}, {"sleep_s", 1.0}}}}},
            {"config_defaults", kDefaults}};
  }

  RunResult run(const RunRequest& request, Sink& sink) override {
    validate(request.config);
    const Json c = merged(request.config);
    const LandscapeModel model(options_from(c));
    std::vector<double> x;
    for (int i = 0; i < model.dim(); ++i) x.push_back(request.params.at("x" + std::to_string(i)).get<double>());

    const std::string failure = failure_for(c["failures"], request.trial_index, request.attempt);
    if (!failure.empty() && failure != "nan") fail_now(failure);

    const double sleep_s = c["sleep_s"].get<double>();
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < sleep_s) {
      if (request.cancel && request.cancel->load()) throw std::runtime_error("cancelled");
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }

    RunResult result;
    result.objectives = {model.objective(x)};
    result.features = model.feature(x);
    base::Rng rng(request.seed);
    const double noise = c["noise"].get<double>();
    if (noise > 0.0)
      for (auto& f : result.features) f += rng.normal(0.0, noise);
    if (failure == "nan") result.features[0] = std::nan("");

    const int points = c["metric_points"].get<int>();
    for (int k = 0; k < points; ++k) {
      // Approaches the objective from below, like a training curve.
      const double t = points > 1 ? static_cast<double>(k) / (points - 1) : 1.0;
      sink.metric("trace", k, result.objectives[0] - (1.0 - t) * (1.0 - t));
      sink.progress(t);
    }
    if (c["artifact"].get<bool>()) {
      const auto path = request.work_dir / "result.json";
      std::ofstream(path) << Json{{"x", x}, {"feature", result.features}}.dump() << '\n';
      result.artifacts.push_back({"result", path});
    }
    return result;
  }
};

}  // namespace podium::tasks::landscape

PODIUM_EXPORT_TASK(podium::tasks::landscape::LandscapeTask, "landscape")
