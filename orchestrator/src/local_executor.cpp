#include "local_executor.h"

#include <poll.h>
#include <unistd.h>

#include <cmath>
#include <cstring>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/store/run_folders.h"
#include "trial_runner.h"

namespace podium::orchestrator {

LocalExecutor::LocalExecutor(std::filesystem::path worker_binary, std::size_t workers)
    : binary_(std::move(worker_binary)), slots_(workers) {
  for (std::size_t i = 0; i < slots_.size(); ++i) slots_[i].index = static_cast<int>(i) + 1;
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  host_ = name;
}

std::size_t LocalExecutor::free_slots() const {
  std::size_t n = 0;
  for (const auto& s : slots_) n += s.key < 0;
  return n;
}

std::string LocalExecutor::submit(const AttemptOrder& order) {
  for (auto& slot : slots_) {
    if (slot.key >= 0) continue;
    if (!slot.process) slot.process = std::make_unique<WorkerProcess>(binary_);
    slot.key = order.key;
    slot.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(order.timeout_s));
    slot.cancel_deadline = Clock::time_point::max();
    // The attempt's stderr (its log lines) goes to the trial's folder, appended across attempts.
    const auto log = order.work_dir / store::kTrialLog;
    if (!slot.process->log_to(log, attempt_log_header(order.attempt)))
      base::log_warning("local executor: cannot write " + log.string() + "; the attempt runs without its log");
    Json message = to_json(order);
    message["type"] = "run";
    slot.process->send(message);
    // A failed send means the worker is dead; poll() sees the closed pipe and reports it.
    return "local:worker-" + std::to_string(slot.index) + "/pid " + std::to_string(slot.process->pid());
  }
  throw base::RuntimeError("local executor: submit() with no free worker");
}

void LocalExecutor::cancel(std::int64_t key) {
  for (auto& slot : slots_) {
    if (slot.key != key || !slot.process) continue;
    slot.process->send({{"type", "cancel"}, {"key", key}});
    // A task that ignores the flag is killed after a grace period.
    slot.cancel_deadline = Clock::now() + std::chrono::seconds(3);
  }
}

void LocalExecutor::handle_message(Slot& slot, const Json& m, std::vector<ExecutorEvent>& events) {
  const std::string type = m.value("type", "");
  if (type == "ready" || slot.key < 0 || m.value("key", std::int64_t{-1}) != slot.key) return;
  ExecutorEvent e;
  e.key = slot.key;
  if (type == "metric") {
    e.kind = ExecutorEvent::Kind::metric;
    e.name = m.value("name", "");
    e.step = m.value("step", 0.0);
    e.value = m["value"].is_number() ? m["value"].get<double>() : std::nan("");
  } else if (type == "progress") {
    e.kind = ExecutorEvent::Kind::progress;
    e.value = m.value("fraction", 0.0);
  } else if (type == "result" || type == "error") {
    const bool cancelled = slot.cancel_deadline != Clock::time_point::max();
    e.state = type == "result" ? "done" : (cancelled ? "cancelled" : "failed");
    if (type == "result") e.result = m;
    else {
      e.error = m.value("message", "task failed");
      e.retry = m.value("retry", true);
    }
    slot.key = -1;
    slot.process->log_to({});
  } else {
    return;
  }
  events.push_back(std::move(e));
}

void LocalExecutor::end_with_death(Slot& slot, std::vector<ExecutorEvent>& events, const std::string& state,
                                   const std::string& why) {
  slot.process->kill_now();
  ExecutorEvent e;
  e.key = slot.key;
  slot.process->wait_exit(e.exit_code, e.signal);
  slot.process->log_to({});
  e.state = state;
  e.error = why;
  if (state == "failed") {
    e.error = e.signal ? "worker killed by signal " + std::to_string(*e.signal) + " (" + strsignal(*e.signal) + ")"
                       : "worker exited with code " + std::to_string(e.exit_code.value_or(-1));
  }
  const std::string tail = slot.process->stderr_tail();
  if (!tail.empty()) e.error += "; stderr: " + tail.substr(tail.size() > 500 ? tail.size() - 500 : 0);
  slot.process.reset();
  if (slot.key >= 0) events.push_back(std::move(e));
  slot.key = -1;
}

std::vector<ExecutorEvent> LocalExecutor::poll(double max_wait_s) {
  std::vector<pollfd> fds;
  std::vector<Slot*> owners;
  auto wait = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(max_wait_s));
  for (auto& slot : slots_) {
    if (!slot.process) continue;
    fds.push_back({slot.process->protocol_fd(), POLLIN, 0});
    owners.push_back(&slot);
    fds.push_back({slot.process->stderr_fd(), POLLIN, 0});
    owners.push_back(&slot);
    if (slot.key >= 0) wait = std::min({wait, slot.deadline, slot.cancel_deadline});
  }
  const auto timeout_ms = std::max<long>(0, std::chrono::duration_cast<std::chrono::milliseconds>(wait - Clock::now()).count());
  ::poll(fds.data(), fds.size(), static_cast<int>(timeout_ms));

  std::vector<ExecutorEvent> events;
  std::vector<Json> messages;
  for (auto& slot : slots_) {
    if (!slot.process) continue;
    slot.process->drain_stderr();
    messages.clear();
    const bool open = slot.process->read_messages(messages);
    for (const auto& m : messages) handle_message(slot, m, events);
    const auto now = Clock::now();
    if (!open) end_with_death(slot, events, "failed", "");
    else if (slot.key >= 0 && now >= slot.deadline)
      end_with_death(slot, events, "timeout", "trial timeout reached; worker killed");
    else if (slot.key >= 0 && now >= slot.cancel_deadline)
      end_with_death(slot, events, "cancelled", "cancelled; worker killed after the grace period");
  }
  return events;
}

}  // namespace podium::orchestrator
