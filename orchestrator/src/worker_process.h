#pragma once
// One `podium worker` child process with pipes to its stdin, protocol stdout and stderr.
#include <sys/types.h>

#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::orchestrator {

class WorkerProcess {
 public:
  /// Starts `binary worker`. The child is killed if this process dies (PR_SET_PDEATHSIG).
  explicit WorkerProcess(const std::filesystem::path& binary);
  ~WorkerProcess();
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  pid_t pid() const { return pid_; }
  int protocol_fd() const { return out_fd_; }
  int stderr_fd() const { return err_fd_; }
  /// Writes one message; false if the worker is gone.
  bool send(const base::Json& message);
  /// Reads what is available on the protocol pipe; complete messages are appended to `out`.
  /// Returns false on end of file (the worker exited or died).
  bool read_messages(std::vector<base::Json>& out);
  /// Reads what is available on stderr into a bounded tail kept for error messages, and into
  /// the log file while one is set.
  void drain_stderr();
  /// Appends the worker's stderr to `path` (created with its folders) from now on, after a
  /// `header`; an empty path ends the log. False (and no log) if the file cannot be opened.
  bool log_to(const std::filesystem::path& path, const std::string& header = "");
  std::string stderr_tail() const { return stderr_tail_; }
  void kill_now();
  /// Reaps the child (blocking); returns exit code or signal.
  void wait_exit(std::optional<int>& exit_code, std::optional<int>& signal);

 private:
  pid_t pid_ = -1;
  int in_fd_ = -1, out_fd_ = -1, err_fd_ = -1, log_fd_ = -1;
  std::string buffer_, stderr_tail_;
  bool reaped_ = false;
};

/// Runs a one-off describe request in a fresh worker process, so a crashing plugin cannot take
/// the caller down. Throws base::UserError with the plugin's message on failure, and
/// base::ConfigError (path inside `config`, problem) when the task rejected a config value.
base::Json describe_task_isolated(const std::filesystem::path& binary, const std::string& task, const base::Json& config);

}  // namespace podium::orchestrator
