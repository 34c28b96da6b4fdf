#pragma once
// Where attempts run. The scheduler drives every executor through this interface and knows
// nothing of processes or clusters; executors know nothing of the store.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::orchestrator {

using base::Json;

/// One attempt of one trial, as the executor needs it. `key` is the store's attempt id.
struct AttemptOrder {
  std::int64_t key = 0;
  std::string task;
  Json config, params, context;
  Json inputs = Json::array();      ///< the trial's hand-over (search.h: SearchSetup::inputs' form)
  Json previous_attempt = nullptr;  ///< {"number", "state", "error"} from the second attempt on
  std::uint64_t seed = 0, trial_index = 0;
  int attempt = 1;
  std::filesystem::path work_dir;  ///< absolute; kept across attempts
  double timeout_s = 3600.0;
};

/// The order as the JSON a worker or a batch job reads (trial_runner.h: run_attempt).
inline Json to_json(const AttemptOrder& o) {
  return {{"key", o.key},
          {"task", o.task},
          {"config", o.config},
          {"params", o.params},
          {"context", o.context},
          {"inputs", o.inputs},
          {"previous_attempt", o.previous_attempt},
          {"seed", o.seed},
          {"trial_index", o.trial_index},
          {"attempt", o.attempt},
          {"work_dir", o.work_dir.string()}};
}

/// What comes back. Every submitted order ends with exactly one `finished` event.
struct ExecutorEvent {
  enum class Kind { metric, progress, placed, finished };
  Kind kind = Kind::finished;
  std::int64_t key = 0;
  // metric / progress
  std::string name;
  double step = 0, value = 0;
  // placed: where the attempt runs now (a batch job id and/or host), once known
  std::string job_id, host;
  // finished: state is "done" (result holds the worker's result message) or one of
  // "failed", "timeout", "cancelled"; for a dead worker, exit_code or signal is set.
  std::string state;
  Json result;
  std::string error;
  std::optional<int> exit_code, signal;
  // failed: false when the task rejected its input (trial_runner.h's attempt_error), so the
  // scheduler does not spend another attempt on it.
  bool retry = true;
};

class Executor {
 public:
  virtual ~Executor() = default;
  /// How many more orders can start now.
  virtual std::size_t free_slots() const = 0;
  /// Starts an order; returns where it runs (e.g. "local:worker-1/pid 1234").
  virtual std::string submit(const AttemptOrder& order) = 0;
  /// Asks a running order to stop; it ends with a `cancelled` event.
  virtual void cancel(std::int64_t key) = 0;
  /// Waits up to max_wait_s for events and returns them (possibly none).
  virtual std::vector<ExecutorEvent> poll(double max_wait_s) = 0;
  virtual std::string host() const = 0;
  /// Takes over an attempt that an earlier scheduler placed (job_id from the store). Executors
  /// whose attempts die with the scheduler (local) cannot and return false.
  virtual bool adopt(const AttemptOrder& order, const std::string& job_id) = 0;
};

}  // namespace podium::orchestrator
