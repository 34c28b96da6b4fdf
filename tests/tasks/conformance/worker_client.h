#pragma once
// A real `podium worker` child (the process the local executor runs trials in), driven over its
// line protocol (orchestrator/src/worker.h) with pipes, for tests that talk to a running trial.
#include <sys/types.h>

#include <chrono>
#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace podium::testing {

class WorkerClient {
 public:
  WorkerClient();   ///< starts `$PODIUM_BIN worker` and waits for its "ready" message
  ~WorkerClient();  ///< closes its stdin, kills it if still running, reaps it
  WorkerClient(const WorkerClient&) = delete;
  WorkerClient& operator=(const WorkerClient&) = delete;

  void send(const nlohmann::json& message);
  /// The next protocol message, or nullopt if none arrives within `timeout` (or the worker died).
  std::optional<nlohmann::json> next(std::chrono::milliseconds timeout);
  /// SIGKILLs the worker (a crash mid-trial) and reaps it.
  void kill();

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int in_fd_ = -1, out_fd_ = -1;
  std::string buffer_;
  std::deque<nlohmann::json> messages_;
};

}  // namespace podium::testing
