#include "process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <stdexcept>
#include <thread>

namespace podium::testing {

namespace fs = std::filesystem;

fs::path podium_binary() {
  const char* bin = std::getenv("PODIUM_BIN");
  if (!bin) throw std::runtime_error("PODIUM_BIN is not set (run the tests through ctest)");
  return bin;
}

namespace {
pid_t start(const std::vector<std::string>& args, const fs::path& cwd, const fs::path& out, const fs::path& err,
            bool own_group = false) {
  const std::string bin = podium_binary().string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (own_group) ::setpgid(0, 0);
    if (::chdir(cwd.c_str()) != 0) ::_exit(126);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, STDOUT_FILENO);
    ::dup2(e, STDERR_FILENO);
    const int null_in = ::open("/dev/null", O_RDONLY);
    ::dup2(null_in, STDIN_FILENO);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(bin.c_str()));
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(bin.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

}  // namespace

int wait_process(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return -WTERMSIG(status);
}

bool wait_until(pid_t pid, const std::function<bool()>& holds, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    if (holds()) return true;
    if (::waitpid(pid, nullptr, WNOHANG) == pid) return false;
    if (timeout_s > 0 && std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

CommandResult run_podium(const std::vector<std::string>& args, const fs::path& cwd) {
  static int counter = 0;
  const fs::path out = cwd / (".out" + std::to_string(++counter)), err = cwd / (".err" + std::to_string(counter));
  const int status = wait_process(start(args, cwd, out, err));
  CommandResult r;
  r.exit_code = status >= 0 ? status : -1;
  r.signal = status < 0 ? -status : 0;
  r.out = file_bytes(out);
  r.err = file_bytes(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

pid_t spawn_podium(const std::vector<std::string>& args, const fs::path& cwd, bool own_group) {
  const pid_t pid = start(args, cwd, cwd / "spawn.out", cwd / "spawn.err", own_group);
  if (own_group) ::setpgid(pid, pid);  // also here, so the group exists before this returns
  return pid;
}

namespace {
// True while some process of `group` is neither stopped nor a zombie (from /proc/<pid>/stat:
// "pid (comm) state ppid pgrp ...", comm may hold spaces or parentheses).
bool group_has_a_running_process(pid_t group) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    std::ifstream in(entry.path() / "stat");
    std::string stat;
    if (!std::getline(in, stat)) continue;
    const auto close = stat.rfind(')');
    if (close == std::string::npos) continue;
    char state = 0;
    long ppid = 0, pgrp = 0;
    if (std::sscanf(stat.c_str() + close + 1, " %c %ld %ld", &state, &ppid, &pgrp) != 3) continue;
    if (pgrp == group && state != 'T' && state != 't' && state != 'Z' && state != 'X') return true;
  }
  return false;
}
}  // namespace

void freeze_group(pid_t group) {
  ::killpg(group, SIGSTOP);
  while (group_has_a_running_process(group)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

TempDir::TempDir() {
  std::random_device rd;
  path_ = fs::temp_directory_path() / ("podium-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void write_file(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

ShellResult shell(const std::string& command) {
  ShellResult r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) r.out.append(buffer, n);
  r.status = ::pclose(pipe);
  return r;
}

}  // namespace podium::testing
