#pragma once
/// The task plugin contract (DESIGN.md "Concepts: Task plugin").
///
/// A task declares its parameter space, strategy features, metrics and fidelity presets
/// (describe) and runs one trial (run). It runs inside a worker process, never inside the
/// scheduler; run() may be called many times on one object, one call at a time.
///
/// The description is plain JSON so the scheduler can hand it to the search layer without either
/// side including the other:
///   {"params":   [{"name", "low", "high", "integer"?}],
///    "features": [{"name", "low", "high", "metric": "euclidean"|"angular", "unit"?}],
///    "metrics":  [{"name", "unit"?, "description"?}],
///    "objectives": ["name", ...],        // objectives[0] is the primary one
///    "strategy_threshold": 0.1,          // optional: feature distance within which two trials
///                                        // are the same strategy (a spec may override it)
///    "presets":  {"smoke": {config}, "quick": {config}, "paper": {config}},
///    "config_defaults": {config}}         // every config key the task accepts, with its default
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::plugins {

using base::Json;

/// Bumped whenever Task, RunRequest, RunResult or TaskDescriptor change layout or meaning.
inline constexpr int kAbiVersion = 1;

/// Where a task reports while it runs; calls are cheap and may come from the run() thread only.
class Sink {
 public:
  virtual ~Sink() = default;
  /// Fraction of the trial done, in [0, 1].
  virtual void progress(double fraction) = 0;
  /// One point of a metric's time series (step: training step, episode or iteration).
  virtual void metric(const std::string& name, double step, double value) = 0;
};

struct RunRequest {
  Json params = Json::object();   ///< {"name": value} for every declared parameter
  Json context = Json::object();  ///< input from the search or an earlier stage
  Json config = Json::object();   ///< task config: defaults, then preset, then the spec's overrides
  std::uint64_t seed = 0;         ///< the only source of randomness a task may use
  std::uint64_t trial_index = 0;
  int attempt = 1;                ///< 1 for the first attempt, 2 for the first retry, ...
  std::filesystem::path work_dir; ///< exists, empty on the first attempt; artifacts go here
  const std::atomic<bool>* cancel = nullptr;  ///< set when the trial must stop; poll it
};

struct Artifact {
  std::string name;              ///< e.g. "policy", "trajectory"
  std::filesystem::path path;    ///< inside work_dir
};

struct RunResult {
  std::vector<double> objectives;
  std::vector<double> features;  ///< as many as the description's "features"
  std::vector<Artifact> artifacts;
  Json info = Json::object();    ///< free-form extra results (stored with the trial)
};

class Task {
 public:
  virtual ~Task() = default;
  /// The description for a resolved config (parameter spaces may depend on it, e.g. a dimension).
  /// describe({}) must work and gives "presets" and "config_defaults".
  virtual Json describe(const Json& config) const = 0;
  /// Runs one trial. Throwing an exception fails the attempt with its message.
  virtual RunResult run(const RunRequest& request, Sink& sink) = 0;
};

}  // namespace podium::plugins
