// The conformance checks of task_conformance.h, run against the real `podium` binary.
#include "task_conformance.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "batch_trial.h"
#include "podium/base/error.h"
#include "podium/plugins/loader.h"
#include "worker_client.h"

namespace podium::testing {
namespace {

namespace fs = std::filesystem;
using base::Json;
using namespace std::chrono_literals;

// --- describe() ---------------------------------------------------------------------------

void expect_named_list(const Json& d, const std::string& key, const std::string& where) {
  ASSERT_TRUE(d.contains(key) && d[key].is_array()) << where << ": \"" << key << "\" is not an array";
  std::set<std::string> names;
  for (const auto& item : d[key]) {
    ASSERT_TRUE(item.is_object() && item.contains("name") && item["name"].is_string()) << where << "." << key << ": " << item;
    EXPECT_TRUE(names.insert(item["name"].get<std::string>()).second) << where << "." << key << ": duplicate " << item["name"];
    for (const char* text : {"unit", "description"})
      if (item.contains(text)) {
        EXPECT_TRUE(item[text].is_string()) << where << "." << key << ": " << item;
      }
  }
}

void expect_box(const Json& item, const std::string& where) {
  ASSERT_TRUE(item.contains("low") && item["low"].is_number() && item.contains("high") && item["high"].is_number())
      << where << ": " << item << " needs numeric low and high";
  const double low = item["low"].get<double>(), high = item["high"].get<double>();
  EXPECT_TRUE(std::isfinite(low) && std::isfinite(high) && low < high) << where << ": " << item;
}

void expect_valid_description(const Json& d, const std::string& where) {
  ASSERT_TRUE(d.is_object()) << where;
  expect_named_list(d, "params", where);
  expect_named_list(d, "features", where);
  expect_named_list(d, "metrics", where);
  for (const auto& p : d["params"]) {
    expect_box(p, where + ".params");
    if (p.contains("integer")) {
      EXPECT_TRUE(p["integer"].is_boolean()) << where << ".params: " << p;
    }
  }
  for (const auto& m : d["metrics"]) {  // the plot's shape (plugins::metric_entry), when declared
    if (m.contains("x")) {
      EXPECT_TRUE(m["x"].is_object() && m["x"].contains("name") && m["x"]["name"].is_string()) << where << ".metrics: " << m;
    }
    if (m.contains("kind")) {
      EXPECT_TRUE(m["kind"] == "learning_curve" || m["kind"] == "evaluation") << where << ".metrics: " << m;
    }
  }
  for (const auto& f : d["features"]) {
    expect_box(f, where + ".features");
    const std::string metric = f.value("metric", "");
    EXPECT_TRUE(metric == "euclidean" || metric == "angular") << where << ".features: " << f;
  }
  ASSERT_TRUE(d.contains("objectives") && d["objectives"].is_array() && !d["objectives"].empty())
      << where << ": \"objectives\" must be a non-empty array";
  for (const auto& o : d["objectives"]) EXPECT_TRUE(o.is_string()) << where << ".objectives: " << o;
  if (d.contains("strategy_threshold")) {
    EXPECT_TRUE(d["strategy_threshold"].is_number() && d["strategy_threshold"].get<double>() > 0) << where;
  }
  ASSERT_TRUE(d.contains("config_defaults") && d["config_defaults"].is_object()) << where << ": no config_defaults";
  if (d.contains("config")) {  // what the config reader accepts (base/config.h), for `podium tasks`
    ASSERT_TRUE(d["config"].is_array()) << where << ": \"config\" is not an array";
    for (const auto& key : d["config"]) EXPECT_TRUE(key.is_object() && key.contains("key")) << where << ".config: " << key;
  }
  ASSERT_TRUE(d.contains("presets") && d["presets"].is_object()) << where << ": no presets";
  for (const char* preset : {"smoke", "quick", "paper"})  // every task has the three fidelity presets
    EXPECT_TRUE(d["presets"].contains(preset)) << where << ": no preset \"" << preset << "\"";
  for (const auto& [name, preset] : d["presets"].items()) {
    ASSERT_TRUE(preset.is_object()) << where << ".presets." << name;
    for (const auto& [key, value] : preset.items())
      EXPECT_TRUE(d["config_defaults"].contains(key)) << where << ".presets." << name << "." << key << " has no default";
  }
}

// The config the scheduler hands a stage's trials: defaults, then the preset, then overrides.
Json resolved(const Json& description, const std::string& preset, const Json& overrides) {
  Json config = description["config_defaults"];
  config.update(description["presets"][preset]);
  config.update(overrides);
  return config;
}

// --- trials through the real binary ---------------------------------------------------------

bool is_time_series(const Json& point) { return point["name"].get<std::string>().rfind("time/", 0) == 0; }

// Metric points with the time/ series' values left out (wall seconds differ between runs).
std::vector<Json> without_times(std::vector<Json> points) {
  for (auto& p : points)
    if (is_time_series(p)) p.erase("value");
  return points;
}

// The case's own inputs (ConformanceCase::inputs), made once per test folder: beside `work_dir`.
Json case_inputs(const ConformanceCase& c, const fs::path& work_dir) {
  static std::map<fs::path, Json> made;
  if (!c.inputs) return Json::array();
  const fs::path dir = work_dir.parent_path() / "inputs";
  auto [at, fresh] = made.try_emplace(dir);
  if (fresh) at->second = c.inputs(dir);
  return at->second;
}

Json order_for(const ConformanceCase& c, const Json& overrides, const fs::path& work_dir, int attempt, std::uint64_t seed,
               const Json& given_inputs = Json::array()) {
  const Json inputs = given_inputs.empty() ? case_inputs(c, work_dir) : given_inputs;
  const auto task = plugins::load_task(c.task);
  Json config = resolved(task->describe(c.base_config), "smoke", c.base_config);
  config.update(overrides);
  Json params = Json::object();
  const Json description = task->describe(config);
  for (const auto& p : description["params"]) {
    const double mid = 0.5 * (p["low"].get<double>() + p["high"].get<double>());
    params[p["name"].get<std::string>()] = p.value("integer", false) ? std::round(mid) : mid;
  }
  const Json previous =
      attempt == 1 ? Json(nullptr) : Json{{"number", attempt - 1}, {"state", "interrupted"}, {"error", "killed by the test"}};
  return order_json({.task = c.task,
                     .config = config,
                     .params = params,
                     .inputs = inputs,
                     .previous_attempt = previous,
                     .seed = seed,
                     .attempt = attempt,
                     .work_dir = work_dir});
}

struct TrialRun {
  Json result;                // result.json with artifact paths relative to the work folder
  std::vector<Json> metrics;  // metrics.jsonl
  fs::path work_dir;
};

// The result with each artifact path made relative to the work folder (two runs use two folders).
Json comparable(Json result, const fs::path& work_dir) {
  for (auto& a : result["artifacts"]) a["path"] = fs::path(a["path"].get<std::string>()).lexically_relative(work_dir).string();
  result.erase("key");
  return result;
}

// One `podium trial --batch` process: order.json, metrics.jsonl and result.json in attempt_dir.
TrialRun run_trial(const Json& order, const fs::path& attempt_dir) {
  const BatchTrial run = run_batch_trial(order, attempt_dir);
  EXPECT_EQ(run.run.exit_code, 0) << "podium trial --batch failed: " << run.run.err;
  EXPECT_EQ(run.result.value("type", ""), "result") << run.result << "\norder: " << order;
  const fs::path work_dir = order["work_dir"].get<std::string>();
  return {comparable(run.result, work_dir), run.metrics, work_dir};
}

// Two smoke trials with one seed, run once per task and shared by the tests that inspect them.
struct SmokeRuns {
  TempDir dir;
  TrialRun first, second;
};

const SmokeRuns& smoke_runs(const ConformanceCase& c) {
  static std::map<std::string, std::unique_ptr<SmokeRuns>> cache;
  auto& slot = cache[c.task + c.base_config.dump() + c.smoke_config.dump()];
  if (!slot) {
    slot = std::make_unique<SmokeRuns>();
    const fs::path a = slot->dir / "a", b = slot->dir / "b";
    slot->first = run_trial(order_for(c, c.smoke_config, a / "trial", 1, 7), a / "attempt-1");
    slot->second = run_trial(order_for(c, c.smoke_config, b / "trial", 1, 7), b / "attempt-1");
  }
  return *slot;
}

// --- the checks ------------------------------------------------------------------------------

TEST_P(TaskConformance, DescribeIsValidAndEveryPresetResolves) {
  const auto task = plugins::load_task(GetParam().task);
  const Json d = task->describe(GetParam().base_config);
  expect_valid_description(d, GetParam().task + " describe(" + GetParam().base_config.dump() + ")");
  for (const auto& [name, preset] : d["presets"].items())
    expect_valid_description(task->describe(resolved(d, name, GetParam().base_config)), GetParam().task + " preset " + name);
  EXPECT_THROW(task->describe({{"no_such_conformance_key", 1}}), base::UserError) << "an unknown config key must be rejected";
}

TEST_P(TaskConformance, SmokeTrialIsDeterministicForASeed) {
  const auto& runs = smoke_runs(GetParam());
  EXPECT_EQ(runs.first.result, runs.second.result);
  EXPECT_EQ(without_times(runs.first.metrics), without_times(runs.second.metrics));
  const auto task = plugins::load_task(GetParam().task);
  Json config = resolved(task->describe(GetParam().base_config), "smoke", GetParam().base_config);
  config.update(GetParam().smoke_config);
  const Json d = task->describe(config);
  EXPECT_EQ(runs.first.result["features"].size(), d["features"].size());
  EXPECT_EQ(runs.first.result["objectives"].size(), d["objectives"].size());
  for (const auto& v : runs.first.result["features"]) EXPECT_TRUE(v.is_number()) << "non-finite feature: " << runs.first.result;
  std::set<std::string> declared;
  for (const auto& m : d["metrics"]) declared.insert(m["name"].get<std::string>());
  for (const auto& m : runs.first.metrics) EXPECT_TRUE(declared.count(m["name"].get<std::string>())) << "undeclared metric " << m;
}

TEST_P(TaskConformance, ArtifactsExistInsideTheWorkFolder) {
  const auto& run = smoke_runs(GetParam()).first;
  std::set<std::string> names;
  for (const auto& a : run.result["artifacts"]) {
    names.insert(a["name"].get<std::string>());
    const fs::path relative = a["path"].get<std::string>();
    EXPECT_FALSE(relative.empty() || *relative.begin() == "..") << a << " is not inside " << run.work_dir;
    EXPECT_TRUE(fs::is_regular_file(run.work_dir / relative)) << a;
    if (fs::is_regular_file(run.work_dir / relative)) {
      EXPECT_EQ(fs::file_size(run.work_dir / relative), a["size"].get<std::uintmax_t>()) << a;
    }
  }
  for (const auto& name : GetParam().artifacts) EXPECT_TRUE(names.count(name)) << "no artifact \"" << name << "\"";
}

// A trial running in a worker (key 1): what it has sent so far.
struct WorkerRun {
  Json result;                // the "result" or "error" message, null while it runs
  std::vector<Json> metrics;  // {"name", "step", "value"}, as in metrics.jsonl
  std::vector<double> progress;
};

// Starts the order's trial in the worker.
WorkerRun start_in(WorkerClient& worker, Json order) {
  order["type"] = "run";
  worker.send(order);
  return {};
}

// Follows the trial until it ends or, mid-run, until it has sent `metric_points` points (for a task
// silent while it works, 0: until `delay_s` passed). Returns whether it ended.
bool follow(WorkerClient& worker, WorkerRun& run, std::size_t metric_points, double delay_s) {
  const auto started = std::chrono::steady_clock::now();
  const auto waited_enough = [&] {
    return metric_points > 0 ? run.metrics.size() >= metric_points
                             : std::chrono::steady_clock::now() - started >= std::chrono::duration<double>(delay_s);
  };
  while (!waited_enough()) {
    const auto m = worker.next(20ms);
    if (!m) {
      if (std::chrono::steady_clock::now() - started > 120s) {
        ADD_FAILURE() << "the trial sent nothing more for 2 minutes";
        return true;
      }
      continue;
    }
    const std::string type = m->value("type", "");
    if (type == "metric") run.metrics.push_back({{"name", (*m)["name"]}, {"step", (*m)["step"]}, {"value", (*m)["value"]}});
    else if (type == "progress") run.progress.push_back((*m)["fraction"].get<double>());
    else {
      run.result = *m;
      return true;
    }
  }
  return false;
}

// Runs the trial to its end in the worker.
WorkerRun run_in(WorkerClient& worker, const Json& order) {
  WorkerRun run = start_in(worker, order);
  follow(worker, run, std::numeric_limits<std::size_t>::max(), 0);
  EXPECT_EQ(run.result.value("type", ""), "result") << run.result << "\norder: " << order;
  run.result = comparable(run.result, order["work_dir"].get<std::string>());
  return run;
}

TEST_P(TaskConformance, CancelIsHonouredWithinTwoSeconds) {
  const auto& c = GetParam();
  TempDir dir;
  WorkerClient worker;
  WorkerRun run = start_in(worker, order_for(c, c.long_config, dir / "trial", 1, 7));
  ASSERT_FALSE(follow(worker, run, static_cast<std::size_t>(c.kill_after_metric_points), c.kill_delay_s))
      << "the long trial ended before the cancel: " << run.result;
  worker.send({{"type", "cancel"}, {"key", 1}});
  const auto cancelled = std::chrono::steady_clock::now();
  std::optional<Json> end;
  while (!end && std::chrono::steady_clock::now() - cancelled < 2s) {
    auto m =
        worker.next(std::chrono::duration_cast<std::chrono::milliseconds>(2s - (std::chrono::steady_clock::now() - cancelled)));
    if (m && m->value("type", "") != "metric" && m->value("type", "") != "progress") end = std::move(m);
  }
  ASSERT_TRUE(end.has_value()) << "no answer within 2 s of the cancel message";
  EXPECT_EQ(end->value("type", ""), "error") << *end;
  // The worker goes on: it answers the next request.
  worker.send({{"type", "describe"}, {"task", c.task}, {"config", Json::object()}});
  const auto description = worker.next(30s);
  ASSERT_TRUE(description.has_value());
  EXPECT_EQ(description->value("type", ""), "description") << *description;
}

// The trial of `config` and `inputs` run whole, and run again in another folder with its worker
// SIGKILLed after `kill_after` metric points (or kill_delay_s) and attempt 2 in a new worker: the
// result and every metric point equal (time/ series: their steps). Returns the whole run.
WorkerRun expect_resumes_to_the_uninterrupted_result(const ConformanceCase& c, const fs::path& dir, const Json& config,
                                                     const Json& inputs, int kill_after) {
  WorkerRun full;
  {
    WorkerClient worker;
    full = run_in(worker, order_for(c, config, dir / "full", 1, 7, inputs));
  }
  // Attempt 1 dies with its worker (SIGKILL) mid-run; attempt 2 runs in a new worker, same folder.
  const fs::path work_dir = dir / "cut";
  WorkerRun first;
  {
    WorkerClient worker;
    first = start_in(worker, order_for(c, config, work_dir, 1, 7, inputs));
    const bool ended = follow(worker, first, static_cast<std::size_t>(kill_after), c.kill_delay_s);
    EXPECT_FALSE(ended) << "the trial finished before the kill: make it longer";
    if (ended) return full;
    worker.kill();
  }
  WorkerRun second;
  {
    WorkerClient worker;
    second = run_in(worker, order_for(c, config, work_dir, 2, 7, inputs));
  }

  EXPECT_EQ(second.result, full.result);
  // Every point either attempt sent is the full run's point; together they cover it.
  std::map<std::pair<std::string, double>, double> expected, seen;
  for (const auto& m : full.metrics) expected[{m["name"], m["step"]}] = m["value"].get<double>();
  for (const auto* attempt : {&first, &second})
    for (const auto& m : attempt->metrics) {
      const std::pair<std::string, double> key{m["name"], m["step"]};
      EXPECT_TRUE(expected.count(key)) << "a point the full run does not have: " << m;
      if (!expected.count(key)) return full;
      if (!is_time_series(m)) {
        EXPECT_EQ(m["value"].get<double>(), expected[key]) << m;
      }
      seen[key] = m["value"].get<double>();
    }
  EXPECT_EQ(seen.size(), expected.size()) << "the attempts together miss points of the full run";
  if (c.resumes_from_checkpoint) {
    EXPECT_FALSE(second.progress.empty() || full.progress.empty()) << "the task reports no progress";
    if (!second.progress.empty() && !full.progress.empty()) {
      EXPECT_GT(second.progress.front(), full.progress.front()) << "attempt 2 started over instead of resuming";
    }
  }
  return full;
}

TEST_P(TaskConformance, InterruptedTrialResumesToTheUninterruptedResult) {
  const auto& c = GetParam();
  TempDir dir;
  expect_resumes_to_the_uninterrupted_result(c, dir.path(), c.resume_config, Json::array(), c.kill_after_metric_points);
}

TEST_P(TaskConformance, WarmStartedTrialTrainsOnAndResumes) {
  const auto& c = GetParam();
  if (!c.warm_start) GTEST_SKIP() << c.task << " has no warm start";
  const auto& source = smoke_runs(c).first;
  const WarmStartCase::Order warm = c.warm_start->order(source.work_dir, source.result);
  TempDir dir;
  const WorkerRun full =
      expect_resumes_to_the_uninterrupted_result(c, dir.path(), warm.config, warm.inputs, c.warm_start->kill_after_metric_points);
  ASSERT_EQ(full.result.value("type", ""), "result") << full.result;
  EXPECT_NE(full.result, source.result) << "the warm-started trial did not train on";
}

}  // namespace

Json smoke_input_trial(const std::string& task, const Json& config, const fs::path& dir, const std::string& stage) {
  const ConformanceCase c{.task = task, .base_config = config, .artifacts = {}};
  const fs::path work_dir = dir / stage;
  const TrialRun run = run_trial(order_for(c, Json::object(), work_dir, 1, 7), dir / (stage + "-attempt"));
  Json input = input_from_smoke(work_dir, run.result);
  input["stage"] = stage;
  return input;
}

Json input_from_smoke(const fs::path& source_dir, const Json& source_result) {
  Json input = {{"stage", "explore"},
                {"stage_index", 0},
                {"trial_index", 0},
                {"params", Json::object()},
                {"objectives", source_result["objectives"]},
                {"features", source_result["features"]},
                {"strategy", 0},
                {"artifacts", Json::object()},
                {"info", source_result["info"]}};
  for (const auto& a : source_result["artifacts"])
    input["artifacts"][a["name"].get<std::string>()] = (source_dir / a["path"].get<std::string>()).string();
  return input;
}

}  // namespace podium::testing
