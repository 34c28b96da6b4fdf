// Resume: train, checkpoint, load into a fresh process, continue -> the same parameters as an
// uninterrupted run with the same seed (single-threaded). And a run SIGKILLed three times while
// it trains with a TrainingCheckpoint, restarted each time, ends like the uninterrupted run.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::vector<std::string> lines(const fs::path& p) {
  std::vector<std::string> out;
  std::istringstream in(read_file(p));
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

void run(const std::string& args) {
  const std::string cmd = std::string(LEARN_RESUME_HELPER) + " " + args;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

fs::path temp_dir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("podium_learn_resume_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void check_resume(const std::string& algo, int first_steps, int total_steps) {
  const fs::path dir = temp_dir(algo);
  const auto ckpt = (dir / "ckpt.pt").string();
  run(algo + " " + std::to_string(total_steps) + " --params " + (dir / "uninterrupted.bin").string());
  run(algo + " " + std::to_string(first_steps) + " --save " + ckpt + " --params " + (dir / "first.bin").string());
  run(algo + " " + std::to_string(total_steps) + " --load " + ckpt + " --params " + (dir / "resumed.bin").string());
  const auto uninterrupted = read_file(dir / "uninterrupted.bin");
  ASSERT_FALSE(uninterrupted.empty());
  EXPECT_NE(read_file(dir / "first.bin"), uninterrupted) << "training after the checkpoint must change parameters";
  EXPECT_TRUE(read_file(dir / "resumed.bin") == uninterrupted) << algo << ": resumed parameters differ";
  fs::remove_all(dir);
}

TEST(Resume, PpoResumedInFreshProcessEqualsUninterruptedRun) { check_resume("ppo", 450, 900); }

TEST(Resume, SacResumedInFreshProcessEqualsUninterruptedRun) { check_resume("sac", 500, 800); }

// Starts the helper; once its stats file has `lines_before_kill` lines, SIGKILLs it. Returns
// whether the kill landed (false: the run finished first).
bool run_and_kill(const std::vector<std::string>& args, const fs::path& stats, std::size_t lines_before_kill) {
  std::vector<char*> argv;
  std::string helper = LEARN_RESUME_HELPER;
  argv.push_back(helper.data());
  std::vector<std::string> copy = args;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (lines(stats).size() >= lines_before_kill) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return true;
    }
    ::usleep(500);
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the helper failed before it was killed";
  return false;
}

void check_sigkill(const std::string& algo, int total_steps, std::vector<std::size_t> kill_at) {
  const fs::path dir = temp_dir("kill_" + algo);
  auto args = [&](const std::string& name) {
    return std::vector<std::string>{
        algo,      std::to_string(total_steps),        "--checkpoint", (dir / (name + ".ckpt")).string(),
        "--stats", (dir / (name + ".stats")).string(), "--params",     (dir / (name + ".bin")).string()};
  };
  std::string uninterrupted_cmd;
  for (const auto& a : args("a")) uninterrupted_cmd += a + " ";
  run(uninterrupted_cmd);
  int kills = 0;
  for (std::size_t at : kill_at) kills += run_and_kill(args("b"), dir / "b.stats", at) ? 1 : 0;
  std::string final_cmd;
  for (const auto& a : args("b")) final_cmd += a + " ";
  run(final_cmd);
  std::printf("%s: %d of %zu SIGKILLs landed during training\n", algo.c_str(), kills, kill_at.size());

  const auto uninterrupted = lines(dir / "a.stats");
  ASSERT_GE(uninterrupted.size(), kill_at.back() + 5);
  // Updates between a checkpoint and a kill are reported again after the restart: the same values.
  std::map<int, std::string> by_update;
  for (const auto& line : lines(dir / "b.stats")) {
    const int update = std::stoi(line);
    const auto [it, inserted] = by_update.emplace(update, line);
    EXPECT_EQ(it->second, line) << "update " << update << " reported differently after a restart";
  }
  std::vector<std::string> resumed;
  for (const auto& [update, line] : by_update) resumed.push_back(line);
  EXPECT_EQ(resumed, uninterrupted);
  EXPECT_TRUE(read_file(dir / "b.bin") == read_file(dir / "a.bin")) << algo << ": final parameters differ";
  fs::remove_all(dir);
}

TEST(Resume, PpoSigkilledThreeTimesEndsWithTheUninterruptedParametersAndStats) { check_sigkill("ppo", 150 * 60, {10, 25, 40}); }

TEST(Resume, SacSigkilledThreeTimesEndsWithTheUninterruptedParametersAndStats) { check_sigkill("sac", 60 * 30, {5, 11, 17}); }

}  // namespace
