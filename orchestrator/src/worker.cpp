#include "worker.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <iostream>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "podium/base/json.h"
#include "trial_runner.h"

namespace podium::orchestrator {

using base::Json;

namespace {

// The protocol channel: a private duplicate of the original stdout.
class Channel {
 public:
  explicit Channel(int fd) : out_(fdopen(fd, "w")) {}
  void send(const Json& message) {
    const std::string line = message.dump() + "\n";
    std::fwrite(line.data(), 1, line.size(), out_);
  }
  void flush() { std::fflush(out_); }
  // Flushes at most every 50 ms while a trial streams metrics, so metrics reach the scheduler
  // live without a system call per point.
  void flush_if_due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_flush_ > std::chrono::milliseconds(50)) {
      flush();
      last_flush_ = now;
    }
  }

 private:
  FILE* out_;
  std::chrono::steady_clock::time_point last_flush_{};
};

class ChannelSink final : public plugins::Sink {
 public:
  ChannelSink(Channel& channel, std::int64_t key) : channel_(channel), key_(key) {}
  void progress(double fraction) override {
    channel_.send({{"type", "progress"}, {"key", key_}, {"fraction", fraction}});
    channel_.flush_if_due();
  }
  void metric(const std::string& name, double step, double value) override {
    channel_.send({{"type", "metric"}, {"key", key_}, {"name", name}, {"step", step}, {"value", value}});
    channel_.flush_if_due();
  }

 private:
  Channel& channel_;
  std::int64_t key_;
};

// Shared between the stdin reader thread and the trial-running main thread.
struct Inbox {
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<Json> requests;
  bool closed = false;
  std::atomic<std::int64_t> running_key{-1};
  std::atomic<bool> cancel{false};
};

void read_stdin(Inbox& inbox) {
  std::string line;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    Json message = Json::parse(line, nullptr, false);
    if (message.is_discarded()) continue;
    if (message.value("type", "") == "cancel") {
      if (message.value("key", std::int64_t{-2}) == inbox.running_key.load()) inbox.cancel = true;
      continue;
    }
    std::lock_guard lock(inbox.mutex);
    inbox.requests.push_back(std::move(message));
    inbox.ready.notify_one();
  }
  std::lock_guard lock(inbox.mutex);
  inbox.closed = true;
  inbox.ready.notify_one();
}

}  // namespace

int run_worker() {
  // Keep the protocol on a private descriptor; the plugin's stdout goes to stderr.
  const int protocol_fd = ::dup(STDOUT_FILENO);
  ::dup2(STDERR_FILENO, STDOUT_FILENO);
  Channel channel(protocol_fd);
  channel.send({{"type", "ready"}, {"pid", ::getpid()}});
  channel.flush();

  Inbox inbox;
  std::thread reader(read_stdin, std::ref(inbox));
  reader.detach();  // blocks in getline until stdin closes; the process exits without joining
  TaskCache tasks;
  for (;;) {
    Json m;
    {
      std::unique_lock lock(inbox.mutex);
      inbox.ready.wait(lock, [&] { return inbox.closed || !inbox.requests.empty(); });
      if (inbox.requests.empty()) break;
      m = std::move(inbox.requests.front());
      inbox.requests.pop_front();
    }
    const std::string type = m.value("type", "");
    const std::int64_t key = m.value("key", std::int64_t{-1});
    try {
      if (type == "describe") {
        channel.send(
            {{"type", "description"}, {"description", tasks.get(m.at("task").get<std::string>()).describe(m.at("config"))}});
      } else if (type == "run") {
        inbox.cancel = false;
        inbox.running_key = key;
        ChannelSink sink(channel, key);
        channel.send(run_attempt(tasks, m, inbox.cancel, sink));
        inbox.running_key = -1;
      }
    } catch (const std::exception& e) {
      inbox.running_key = -1;
      channel.send(attempt_error(key, e));
    }
    channel.flush();
  }
  return 0;
}

}  // namespace podium::orchestrator
