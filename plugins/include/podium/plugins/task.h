#pragma once
/// The task plugin contract (docs/architecture.md "Concepts").
///
/// A task declares its parameter space, strategy features, metrics and fidelity presets
/// (describe) and runs one trial (run). It runs inside a worker process, never inside the
/// scheduler; run() may be called many times on one object, one call at a time.
///
/// The description is plain JSON so the scheduler can hand it to the search layer without either
/// side including the other:
///   {"params":   [{"name", "low", "high", "integer"?}],
///    "features": [{"name", "low", "high", "metric": "euclidean"|"angular", "unit"?, "description"?}],
///    "metrics":  [{"name", "unit"?, "description"?, "x"?: {"name", "unit"?},
///                  "kind"?: "learning_curve"|"evaluation", "range"?: [low, high]}],
///    "objectives": ["name", ...],        // objectives[0] is the primary one
///    "objective_info": [{"name", "unit"?, "description"?}],  // optional: what each objective is,
///                                        // in the order of "objectives" (set_objectives writes both)
///    "strategy_threshold": 0.1,          // optional: feature distance within which two trials
///                                        // are the same strategy (a spec may override it)
///    "presets":  {"smoke": {config}, "quick": {config}, "paper": {config}},
///    "config": [{"key", "type", "default"?, ...}],  // optional: the keys it accepts, as
///                                        // base::ConfigReader::describe gives them
///    "config_defaults": {config}}         // every config key the task accepts, with its default
///
/// Names: describe(config) gets the stage's resolved config, so a task whose stages mean different
/// things by their objectives names them per stage (the get-up's Evaluate stage: the mean slowed
/// success and the fast success). `podium trials`, `export`, `status`, `summary` and the dashboard
/// show objectives and features by these names and units, in this order.
///
/// Result tables: RunResult::info["table"], when a task gives one, is what the trial found as a
/// small table, shown by `podium summary` (a stage's trials' tables with the same columns, one under
/// the other, each row led by its trial's name) and on the dashboard's trial page:
///   {"title": "...", "columns": [{"name", "unit"?}], "rows": [[cell, ...], ...]}
/// with one cell per column, each a number, a string or null (not measured). See result_table.
///
/// Config: a task reads its config with base::ConfigReader (validating in describe and run) and
/// describes it from the same code. describe(config) throws base::ConfigError for a value it
/// does not accept; `podium submit` reports it at its JSON path in the spec, exit 2.
///
/// Trial folder and attempts (docs/architecture.md "Concepts"): an attempt that ends early (the scheduler
/// killed, the worker crashed, a timeout, a Slurm requeue) is retried with the same trial index,
/// params, inputs and seed, and the same `work_dir`, which no executor empties between attempts.
/// A long-running task checkpoints there and, on a later attempt, continues from the last
/// checkpoint it finds; `attempt` and `previous_attempt` say why it runs again. Write each
/// checkpoint whole (a temporary file renamed into place, as learn::TrainingCheckpoint and
/// base::write_json_file_atomic do): a kill can land mid-write. Decide from
/// what the folder holds, not from `attempt` alone: a Slurm requeue runs the same attempt again.
/// Metric points are keyed by (name, step): a point whose step the trial already has (from an
/// earlier attempt) is dropped. A point sent just before a kill may never have been stored while
/// the checkpoint after it was written, so a resumed task re-sends every point up to its
/// checkpoint, then the steps it runs again; nothing is stored twice. learn::TrainingCheckpoint
/// does this for a task that reports its points through it.
///
/// Tools: a task may ship a command-line tool (curve editing, data preparation), reached as
/// `podium tool TASK COMMAND [ARGS...]`. tools() names its commands; tool() runs one in the
/// `podium` process itself (not in a worker), writing to the given streams.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::plugins {

using base::Json;

/// What a metric's points are plotted against: the quantity its steps count, and its unit.
struct MetricAxis {
  std::string name;  ///< e.g. "environment steps", "samples", "κ", "strength β"
  std::string unit;  ///< empty: a count or a pure number
};

/// A metric's plot: its x axis, whether it is a learning curve (a value over training, drawn as a
/// line) or an evaluation (one value per setting of its axis, drawn as points), and the value's
/// range when it has one (a rate: [0, 1]).
struct MetricShape {
  MetricAxis x = {"step", ""};
  bool evaluation = false;
  bool rate = false;  ///< a fraction: plotted on [0, 1]
};

/// One entry of a description's "metrics" list; an empty unit is left out. A description written
/// without "x", "kind" or "range" (older tasks, older databases) reads as a learning curve over
/// "step" with no fixed range; the dashboard draws it so.
inline Json metric_entry(const std::string& name, const std::string& unit, const std::string& description,
                         const MetricShape& shape = {}) {
  Json m = {{"name", name}, {"description", description}};
  if (!unit.empty()) m["unit"] = unit;
  m["x"] = {{"name", shape.x.name}};
  if (!shape.x.unit.empty()) m["x"]["unit"] = shape.x.unit;
  m["kind"] = shape.evaluation ? "evaluation" : "learning_curve";
  if (shape.rate) m["range"] = {0.0, 1.0};
  return m;
}

/// One entry of a description's "objective_info" (what an objective means); an empty unit is left out.
inline Json objective_entry(const std::string& name, const std::string& unit, const std::string& description) {
  return metric_entry(name, unit, description);
}

/// Sets a description's "objectives" (the names) and "objective_info" (the entries) from `entries`
/// (objective_entry's), in their order: the first is the primary objective.
inline void set_objectives(Json& description, const Json& entries) {
  Json names = Json::array();
  for (const Json& e : entries) names.push_back(e.at("name"));
  description["objectives"] = names;
  description["objective_info"] = entries;
}

/// One column of a result table (see "Result tables" above); an empty unit is left out.
inline Json table_column(const std::string& name, const std::string& unit = "") {
  Json c = {{"name", name}};
  if (!unit.empty()) c["unit"] = unit;
  return c;
}

/// A result table for RunResult::info["table"]: `columns` of table_column, `rows` of cells.
inline Json result_table(const std::string& title, const Json& columns, const Json& rows) {
  return {{"title", title}, {"columns", columns}, {"rows", rows}};
}

/// Bumped whenever Task, RunRequest, RunResult or TaskDescriptor change layout or meaning.
inline constexpr int kAbiVersion = 4;

/// Where a task reports while it runs; calls are cheap and may come from the run() thread only.
class Sink {
 public:
  virtual ~Sink() = default;
  /// Fraction of the trial done, in [0, 1].
  virtual void progress(double fraction) = 0;
  /// One point of a metric's time series (step: training step, episode or iteration).
  virtual void metric(const std::string& name, double step, double value) = 0;
};

/// One earlier-stage trial handed to this trial (docs/architecture.md "Stage hand-over"). The stage's spec
/// `inputs` selects them from finished trials of earlier stages when the stage starts; they are
/// stored with the stage, so every attempt and a resumed campaign see the same ones.
struct InputTrial {
  std::string stage;    ///< the earlier stage's name
  int stage_index = 0;  ///< its position in the campaign's stages
  std::int64_t trial_index = 0;
  Json params = Json::object();
  std::vector<double> objectives, features;
  std::optional<std::int64_t> strategy;                    ///< its strategy id in its stage, if it has features
  std::map<std::string, std::filesystem::path> artifacts;  ///< absolute paths, by artifact name
  Json info = Json::object();                              ///< its RunResult::info (e.g. the strength a get-up policy passed at)
};

/// How the trial's previous attempt ended (see the header comment).
struct PreviousAttempt {
  int number = 0;     ///< its attempt number (attempt - 1)
  std::string state;  ///< "interrupted" (the scheduler stopped), "failed" (threw, crashed,
                      ///< invalid result), "timeout"
  std::string error;  ///< the reason recorded for it
};

struct RunRequest {
  Json params = Json::object();   ///< {"name": value} for every declared parameter
  Json context = Json::object();  ///< input from the search (e.g. novel-policy seeking's features)
  Json config = Json::object();   ///< task config: defaults, then preset, then the spec's overrides
  std::uint64_t seed = 0;         ///< the only source of randomness a task may use
  std::uint64_t trial_index = 0;
  int attempt = 1;                                  ///< 1 for the first attempt, 2 for the first retry, ...
  std::optional<PreviousAttempt> previous_attempt;  ///< set from the second attempt on
  /// The stage's hand-over: with inputs `"per_trial": "all"` every selected earlier trial, in
  /// selection order; with `"each"` exactly one (trial i gets input i mod n, or under
  /// novel-policy seeking the input it seeks a novel policy for); empty without inputs.
  std::vector<InputTrial> inputs;
  /// Exists; empty on the first attempt, kept as the last attempt left it on later ones.
  /// Artifacts and checkpoints go here (under Slurm, leave the `slurm-attempt-K/` folders alone).
  std::filesystem::path work_dir;
  const std::atomic<bool>* cancel = nullptr;  ///< set when the trial must stop; poll it
};

struct Artifact {
  std::string name;            ///< e.g. "policy", "trajectory"
  std::filesystem::path path;  ///< inside work_dir
};

struct RunResult {
  std::vector<double> objectives;
  std::vector<double> features;  ///< as many as the description's "features"
  std::vector<Artifact> artifacts;
  Json info = Json::object();  ///< free-form extra results (stored with the trial)
};

/// One command of a task's tool (Task::tools), as `podium tool TASK --help` lists it.
struct ToolCommand {
  std::string name;      ///< e.g. "extract"
  std::string synopsis;  ///< its arguments, e.g. "CLIP --out FILE [--method samples|fit]"
  std::string summary;   ///< what it does, one line
};

class Task {
 public:
  virtual ~Task() = default;
  /// The description for a resolved config (parameter spaces may depend on it, e.g. a dimension).
  /// describe({}) must work and gives "presets" and "config_defaults".
  virtual Json describe(const Json& config) const = 0;
  /// Runs one trial. Throwing an exception fails the attempt with its message.
  virtual RunResult run(const RunRequest& request, Sink& sink) = 0;
  /// The commands of the task's tool; none by default.
  virtual std::vector<ToolCommand> tools() const { return {}; }
  /// Runs one tool command: args[0] is a command tools() names, the rest its arguments
  /// (`COMMAND --help` prints its options on `out`). Returns the exit code: 0 done, 2 bad usage or
  /// input (one line on `err` naming the file, the JSON path and the value), 1 a failure. A thrown
  /// base::UserError is shown as one line with exit 2, any other exception with exit 1.
  virtual int tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    (void)args;
    (void)out;
    err << "this task has no tools\n";
    return 2;
  }
};

}  // namespace podium::plugins
