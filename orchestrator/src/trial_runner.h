#pragma once
// Runs one attempt of a trial inside this process: the shared core of `podium worker` (local
// executor, results over a pipe) and `podium trial` (Slurm executor, results in files).
#include <atomic>
#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <string>

#include "podium/base/json.h"
#include "podium/plugins/task.h"

namespace podium::orchestrator {

/// Plugins loaded once per process.
class TaskCache {
 public:
  plugins::Task& get(const std::string& name);

 private:
  std::map<std::string, std::shared_ptr<plugins::Task>> tasks_;
};

/// Runs the attempt described by `order` (an AttemptOrder as JSON: key, task, config, params,
/// context, inputs, previous_attempt, seed, trial_index, attempt, work_dir; the work folder is
/// created if missing, never emptied) and returns the result message
/// {"type":"result", "key", "objectives", "features", "artifacts":[{name,path,sha256,size}], "info"}.
/// Throws whatever the task throws.
base::Json run_attempt(TaskCache& tasks, const base::Json& order, const std::atomic<bool>& cancel, plugins::Sink& sink);

/// The error message for an attempt that threw `e`: {"type":"error", "key", "message"}, with
/// config_path and problem for a base::ConfigError (so submit can name the value inside the spec)
/// and "retry": false for a base::UserError, the task's verdict on its own input, which another
/// attempt with the same input would only repeat.
base::Json attempt_error(std::int64_t key, const std::exception& e);

/// The line a trial's log (store::kTrialLog in its folder) gets before each attempt's output:
/// "podium: attempt N started YYYY-MM-DD HH:MM:SS UTC".
std::string attempt_log_header(int attempt);

/// `podium trial --batch FILE`: runs the order named on line $SLURM_ARRAY_TASK_ID of FILE,
/// appending metrics to <attempt folder>/metrics.jsonl and writing result.json atomically.
int run_batch_trial(const std::string& batch_file);

}  // namespace podium::orchestrator
