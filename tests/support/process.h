#pragma once
// Test support: run the real `podium` binary (path in PODIUM_BIN, set by CTest) as a child
// process, and temporary folders that clean up after themselves.
#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace podium::testing {

struct CommandResult {
  int exit_code = -1;  // -1 if killed by a signal
  int signal = 0;
  std::string out, err;
};

/// The podium binary under test.
std::filesystem::path podium_binary();

/// Runs `podium args...` to completion with the given working folder.
CommandResult run_podium(const std::vector<std::string>& args, const std::filesystem::path& cwd);

/// Starts `podium args...` in the background (stdout/stderr to files in cwd); returns its pid.
/// With `own_group` the process leads a process group of its own, which its workers join, so a
/// test can freeze or kill it with them (freeze_group, ::killpg).
pid_t spawn_podium(const std::vector<std::string>& args, const std::filesystem::path& cwd, bool own_group = false);

/// Stops every process of the group (SIGSTOP) and returns once each one is stopped or gone, so
/// what they left on disk can be read without it changing underneath. ::killpg(group, SIGCONT)
/// lets them go on.
void freeze_group(pid_t group);

/// Waits for a spawned process; returns its exit code, or -signal.
int wait_process(pid_t pid);

/// Polls `holds` every 20 ms until it is true (returns true), or the spawned process `pid` has
/// exited (then reaped) or `timeout_s` has passed, if above 0 (returns false).
bool wait_until(pid_t pid, const std::function<bool()>& holds, double timeout_s = 0);

/// A fresh folder under the system temp folder, removed by the destructor.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

/// Writes text to a file.
void write_file(const std::filesystem::path& path, const std::string& text);

/// A file's bytes ("" when it cannot be read).
std::string file_bytes(const std::filesystem::path& path);

struct ShellResult {
  int status = -1;  ///< pclose's wait status (WIFEXITED/WEXITSTATUS); -1 when the shell could not start
  std::string out;  ///< its stdout
};

/// Runs `command` through /bin/sh to completion and captures its stdout (for the Python and
/// shell scripts tests compare against; the podium binary goes through run_podium).
ShellResult shell(const std::string& command);

}  // namespace podium::testing
