#include "worker_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "podium/base/config.h"
#include "podium/base/error.h"

namespace podium::orchestrator {

using base::Json;

namespace {
// A log write that fails (disk full) loses log lines, never the trial: errors are ignored.
void write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    data += n, size -= static_cast<std::size_t>(n);
  }
}

void make_pipe(int fds[2]) {
  if (::pipe2(fds, O_CLOEXEC) != 0) throw base::RuntimeError(std::string("worker: pipe failed: ") + std::strerror(errno));
}
}  // namespace

WorkerProcess::WorkerProcess(const std::filesystem::path& binary) {
  int in[2], out[2], err[2];
  make_pipe(in);
  make_pipe(out);
  make_pipe(err);
  const pid_t parent = ::getpid();
  pid_ = ::fork();
  if (pid_ < 0) throw base::RuntimeError(std::string("worker: fork failed: ") + std::strerror(errno));
  if (pid_ == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);  // the parent died before prctl took effect
    ::dup2(in[0], STDIN_FILENO);
    ::dup2(out[1], STDOUT_FILENO);
    ::dup2(err[1], STDERR_FILENO);
    ::signal(SIGINT, SIG_IGN);  // Ctrl-C on the terminal reaches the scheduler, which decides
    ::execl(binary.c_str(), binary.c_str(), "worker", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(in[0]);
  ::close(out[1]);
  ::close(err[1]);
  in_fd_ = in[1];
  out_fd_ = out[0];
  err_fd_ = err[0];
  ::fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  ::fcntl(err_fd_, F_SETFL, O_NONBLOCK);
}

WorkerProcess::~WorkerProcess() {
  if (in_fd_ >= 0) ::close(in_fd_);
  if (!reaped_) {
    kill_now();
    std::optional<int> code, sig;
    wait_exit(code, sig);
  }
  ::close(out_fd_);
  ::close(err_fd_);
  if (log_fd_ >= 0) ::close(log_fd_);
}

bool WorkerProcess::send(const Json& message) {
  const std::string line = message.dump() + "\n";
  std::size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::write(in_fd_, line.data() + written, line.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    written += static_cast<std::size_t>(n);
  }
  return true;
}

bool WorkerProcess::read_messages(std::vector<Json>& out) {
  char chunk[65536];
  bool open = true;
  for (;;) {
    const ssize_t n = ::read(out_fd_, chunk, sizeof chunk);
    if (n > 0) {
      buffer_.append(chunk, static_cast<std::size_t>(n));
      continue;
    }
    if (n == 0) open = false;
    else if (errno == EINTR) continue;
    break;  // EAGAIN: nothing more for now
  }
  std::size_t start = 0;
  for (std::size_t nl; (nl = buffer_.find('\n', start)) != std::string::npos; start = nl + 1) {
    Json m = Json::parse(buffer_.begin() + static_cast<long>(start), buffer_.begin() + static_cast<long>(nl), nullptr, false);
    if (!m.is_discarded()) out.push_back(std::move(m));
  }
  buffer_.erase(0, start);
  return open;
}

void WorkerProcess::drain_stderr() {
  char chunk[4096];
  ssize_t n;
  while ((n = ::read(err_fd_, chunk, sizeof chunk)) > 0) {
    if (log_fd_ >= 0) write_all(log_fd_, chunk, static_cast<std::size_t>(n));
    stderr_tail_.append(chunk, static_cast<std::size_t>(n));
    if (stderr_tail_.size() > 2000) stderr_tail_.erase(0, stderr_tail_.size() - 2000);
  }
}

bool WorkerProcess::log_to(const std::filesystem::path& path, const std::string& header) {
  drain_stderr();  // what came before belongs to the previous log
  if (log_fd_ >= 0) ::close(log_fd_);
  log_fd_ = -1;
  if (path.empty()) return true;
  std::error_code ignored;
  std::filesystem::create_directories(path.parent_path(), ignored);
  log_fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd_ < 0) return false;
  write_all(log_fd_, header.data(), header.size());
  return true;
}

void WorkerProcess::kill_now() {
  if (pid_ > 0 && !reaped_) ::kill(pid_, SIGKILL);
}

void WorkerProcess::wait_exit(std::optional<int>& exit_code, std::optional<int>& signal) {
  if (reaped_) return;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
  if (WIFEXITED(status)) exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) signal = WTERMSIG(status);
}

Json describe_task_isolated(const std::filesystem::path& binary, const std::string& task, const Json& config) {
  WorkerProcess worker(binary);
  worker.send({{"type", "describe"}, {"task", task}, {"config", config}});
  std::vector<Json> messages;
  for (;;) {
    pollfd fds[2] = {{worker.protocol_fd(), POLLIN, 0}, {worker.stderr_fd(), POLLIN, 0}};
    ::poll(fds, 2, 30000);
    worker.drain_stderr();
    const bool open = worker.read_messages(messages);
    for (const auto& m : messages) {
      if (m.value("type", "") == "description") return m["description"];
      if (m.value("type", "") == "error" && m.contains("config_path"))
        throw base::ConfigError("", m["config_path"].get<std::string>(), m.value("problem", ""));
      if (m.value("type", "") == "error") throw base::UserError(m.value("message", "plugin error"));
    }
    messages.clear();
    if (!open) {
      std::optional<int> code, sig;
      worker.wait_exit(code, sig);
      throw base::UserError("plugin \"" + task + "\": worker died while describing the task (" +
                            (sig ? "signal " + std::to_string(*sig) : "exit code " + std::to_string(code.value_or(-1))) + ")" +
                            (worker.stderr_tail().empty() ? "" : ": " + worker.stderr_tail()));
    }
  }
}

}  // namespace podium::orchestrator
