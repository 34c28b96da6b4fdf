#pragma once
// The local executor: a pool of persistent worker processes on this machine. Each worker loads
// plugins once and runs one attempt at a time; a worker that dies (signal, exit) or overruns the
// trial timeout is killed and replaced, losing only the attempt in hand.
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "executor.h"
#include "worker_process.h"

namespace podium::orchestrator {

class LocalExecutor final : public Executor {
 public:
  LocalExecutor(std::filesystem::path worker_binary, std::size_t workers);
  std::size_t free_slots() const override;
  std::string submit(const AttemptOrder& order) override;
  void cancel(std::int64_t key) override;
  std::vector<ExecutorEvent> poll(double max_wait_s) override;
  std::string host() const override { return host_; }
  bool adopt(const AttemptOrder&, const std::string&) override { return false; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Slot {
    std::unique_ptr<WorkerProcess> process;  // null until first use or after a death
    std::int64_t key = -1;                   // attempt in hand, -1 when idle
    Clock::time_point deadline;
    Clock::time_point cancel_deadline = Clock::time_point::max();
    int index = 0;
  };
  void handle_message(Slot& slot, const Json& m, std::vector<ExecutorEvent>& events);
  void end_with_death(Slot& slot, std::vector<ExecutorEvent>& events, const std::string& state, const std::string& why);

  std::filesystem::path binary_;
  std::vector<Slot> slots_;
  std::string host_;
};

}  // namespace podium::orchestrator
