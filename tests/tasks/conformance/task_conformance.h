#pragma once
// The task conformance suite: the checks every
// task plugin passes. A task joins with one line in its test file,
//   PODIUM_TASK_CONFORMANCE(Landscape, {.task = "landscape", .long_config = {{"sleep_s", 60.0}}});
// and its test target links podium_task_conformance (tests/tasks/CMakeLists.txt). Trials run in
// the real `podium` binary: `podium trial --batch` (the Slurm path: order.json in, metrics.jsonl
// and result.json out) for the smoke trials, `podium worker` (the local executor's process,
// driven over its protocol) for cancellation and for the interrupted trial.
//   DescribeIsValidAndEveryPresetResolves  params, features, metrics, objectives, presets and
//                                          config_defaults are well formed, for describe({}) and
//                                          for every preset; an unknown config key is rejected
//   SmokeTrialIsDeterministicForASeed      two runs, same result.json and metric stream; sizes as
//                                          declared; every metric declared
//   ArtifactsExistInsideTheWorkFolder      the case's artifacts are returned, exist, have the
//                                          reported size and lie inside work_dir
//   CancelIsHonouredWithinTwoSeconds       a long trial in a worker ends with an error (not a
//                                          result) within 2 s of the cancel message
//   InterruptedTrialResumesToTheUninterruptedResult
//                                          the worker SIGKILLed mid-run, attempt 2 in a new worker
//                                          and the same trial folder: the result and every metric
//                                          point equal a full run's
//   WarmStartedTrialTrainsOnAndResumes     for a task with a warm start: a trial trained on from
//                                          the smoke trial differs from it, and killed mid-run
//                                          (after the copy of its source, before or after its
//                                          first save) resumes to the uninterrupted warm trial
// Metric series under time/ (wall seconds, character/training_stage.h) differ between runs: only
// their names and steps are compared.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::testing {

/// A trial that trains on from the smoke trial (a warm start): its config (on the smoke preset and
/// base_config) and inputs, made from the smoke trial's folder and result.json.
struct WarmStartCase {
  struct Order {
    base::Json config = base::Json::object();
    base::Json inputs = base::Json::array();
  };
  std::function<Order(const std::filesystem::path& source_dir, const base::Json& source_result)> order;
  int kill_after_metric_points = 0;  ///< as ConformanceCase's, for the warm trial
};

/// The smoke trial as an input trial of stage "explore" (index 0, strategy 0): its objectives,
/// features, info, and every artifact at its path under source_dir — what a WarmStartCase's order
/// hands the warm trial.
base::Json input_from_smoke(const std::filesystem::path& source_dir, const base::Json& source_result);

/// A smoke trial of `task` with `config` (on the smoke preset) run through the real binary in
/// `dir`, as an input trial of stage `stage` (index 0, strategy 0; input_from_smoke's form): for a
/// case whose trials need earlier stages' trials (ConformanceCase::inputs).
base::Json smoke_input_trial(const std::string& task, const base::Json& config, const std::filesystem::path& dir,
                             const std::string& stage);

struct ConformanceCase {
  std::string task;                                 ///< plugin name
  base::Json base_config = base::Json::object();    ///< on the smoke preset, under every trial's config (e.g. the stage)
  base::Json smoke_config = base::Json::object();   ///< on top of the smoke preset: the smoke trial
  base::Json long_config = base::Json::object();    ///< on the smoke preset: runs ≥ 10 s unless cancelled
  base::Json resume_config = base::Json::object();  ///< on the smoke preset: long enough to be killed mid-run
  /// The long and resume trials are cancelled / killed once they have sent this many metric
  /// points, or, for a task that reports nothing while it works (0), after kill_delay_s.
  int kill_after_metric_points = 0;
  double kill_delay_s = 0.3;
  /// Attempt 2 continues from a checkpoint: its first progress report is beyond a fresh start's.
  bool resumes_from_checkpoint = false;
  std::vector<std::string> artifacts;                      ///< artifact names every trial returns
  std::optional<WarmStartCase> warm_start = std::nullopt;  ///< none: the task has no warm start
  /// The input trials every trial of the case gets (a stage that needs earlier stages' trials),
  /// made in the given folder once per test (e.g. with smoke_input_trial); none: no inputs.
  std::function<base::Json(const std::filesystem::path& dir)> inputs = {};
};

class TaskConformance : public ::testing::TestWithParam<ConformanceCase> {};

/// Failure messages name the task, not the case's bytes.
inline void PrintTo(const ConformanceCase& c, std::ostream* out) {
  *out << c.task;
  if (c.base_config.contains("stage")) *out << " " << c.base_config["stage"].get<std::string>();
}

}  // namespace podium::testing

#define PODIUM_TASK_CONFORMANCE(Name, ...)  \
  using ::podium::testing::TaskConformance; \
  INSTANTIATE_TEST_SUITE_P(Name, TaskConformance, ::testing::Values(::podium::testing::ConformanceCase __VA_ARGS__))
