// Resume: train, checkpoint, load into a fresh process, continue -> the same parameters as an
// uninterrupted run with the same seed (single-threaded).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void run(const std::string& args) {
  const std::string cmd = std::string(LEARN_RESUME_HELPER) + " " + args;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

void check_resume(const std::string& algo, int first_steps, int total_steps) {
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_resume_" + algo + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
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

}  // namespace
