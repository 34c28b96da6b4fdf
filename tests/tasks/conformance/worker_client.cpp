#include "worker_client.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>

#include "process.h"

namespace podium::testing {

WorkerClient::WorkerClient() {
  int in[2], out[2];
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("worker client: pipe failed");
  const std::string bin = podium_binary().string();
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("worker client: fork failed");
  if (pid_ == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // a crashed test leaves no worker behind
    ::dup2(in[0], STDIN_FILENO);
    ::dup2(out[1], STDOUT_FILENO);
    ::execl(bin.c_str(), bin.c_str(), "worker", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(in[0]);
  ::close(out[1]);
  in_fd_ = in[1];
  out_fd_ = out[0];
  const auto ready = next(std::chrono::seconds(30));
  if (!ready || ready->value("type", "") != "ready") throw std::runtime_error("worker client: no \"ready\" from the worker");
}

WorkerClient::~WorkerClient() {
  ::close(in_fd_);
  kill();
  ::close(out_fd_);
}

void WorkerClient::kill() {
  if (reaped_) return;
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
  reaped_ = true;
}

void WorkerClient::send(const nlohmann::json& message) {
  const std::string line = message.dump() + "\n";
  if (::write(in_fd_, line.data(), line.size()) != static_cast<ssize_t>(line.size()))
    throw std::runtime_error("worker client: write to the worker failed");
}

std::optional<nlohmann::json> WorkerClient::next(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (messages_.empty()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd p{out_fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
    char chunk[4096];
    const ssize_t n = ::read(out_fd_, chunk, sizeof chunk);
    if (n <= 0) return std::nullopt;  // the worker exited
    buffer_.append(chunk, static_cast<std::size_t>(n));
    for (std::size_t end; (end = buffer_.find('\n')) != std::string::npos; buffer_.erase(0, end + 1))
      messages_.push_back(nlohmann::json::parse(buffer_.substr(0, end)));
  }
  auto m = std::move(messages_.front());
  messages_.pop_front();
  return m;
}

}  // namespace podium::testing
