// Trials resume from their own folder (the orchestrator's side): a later attempt
// runs in the folder the earlier one left, is told how that one ended, and the metric steps it
// sends again are not stored twice. Real `podium run` with the probe task, which checkpoints in
// its work folder.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;
using store::Store;

Json probe_campaign(const Json& config, int trials, int retries) {
  return {{"name", "resume"},
          {"seed", 3},
          {"workers", 2},
          {"retries", retries},
          {"trial_timeout_s", 60},
          {"stages", Json::array({{{"name", "train"},
                                   {"task", "probe"},
                                   {"config", config},
                                   {"search", {{"algorithm", "random"}}},
                                   {"budget", {{"trials", trials}}}}})}};
}

// The probe checkpoints every 2 steps and throws after sending step 4 on its first attempt: the
// retry resumes from the checkpoint at step 4 and sends steps 4..7.
TEST(TrialResume, ARetryResumesInTheSameFolderAndStoresEachMetricStepOnce) {
  TempDir dir;
  const auto id = std::stoll(podium::testing::submit_spec(
      dir.path(), probe_campaign({{"steps", 8}, {"checkpoint_every", 2}, {"fail_step", 4}, {"fail_attempts", 1}}, 3, 1)));
  const auto r = run_podium({"run"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto s = Store::open(dir / "podium.db", Store::Access::read_only);
  const auto trials = s->trials(s->stages(id).at(0).id);
  ASSERT_EQ(trials.size(), 3u);
  for (const auto& t : trials) {
    SCOPED_TRACE("trial " + std::to_string(t.index));
    EXPECT_EQ(t.state, "done");
    EXPECT_EQ(t.attempts, 2);
    EXPECT_EQ(t.result_info["attempt"], 2);
    EXPECT_EQ(t.result_info["resumed_from_step"], 4);
    const Json previous = t.result_info["previous_attempt"];
    EXPECT_EQ(previous["number"], 1);
    EXPECT_EQ(previous["state"], "failed");
    EXPECT_NE(previous["error"].get<std::string>().find("probe: injected failure at step 4"), std::string::npos) << previous;
    const auto points = s->metrics(t.id);
    ASSERT_EQ(points.size(), 8u);
    for (std::size_t k = 0; k < points.size(); ++k) {
      EXPECT_EQ(points[k].step, static_cast<double>(k));
      EXPECT_EQ(points[k].attempt, k <= 4 ? 1 : 2) << "step " << k;  // step 4 came again from attempt 2
    }
    EXPECT_TRUE(std::filesystem::exists(s->artifacts(t.id).at(0).path));
    // Both attempts' log lines, in order, in the trial's folder (where the artifact is).
    const std::string log =
        podium::testing::file_bytes(std::filesystem::path(s->artifacts(t.id).at(0).path).parent_path() / "trial.log");
    std::size_t at = 0;
    for (const char* line : {"podium: attempt 1 started ", "probe: attempt 1 starts at step 0", "podium: attempt 2 started ",
                             "probe: attempt 2 starts at step 4"}) {
      at = log.find(line, at);
      ASSERT_NE(at, std::string::npos) << "no '" << line << "' after the lines before it in:\n" << log;
    }
  }
}

// A task's own verdict on its input (base::UserError) ends the trial at once: another attempt
// would repeat it. An injected std::runtime_error (above) is retried.
TEST(TrialResume, ATaskThatRejectsItsInputIsNotRetried) {
  TempDir dir;
  const auto id = std::stoll(podium::testing::submit_spec(dir.path(), probe_campaign({{"reject", true}}, 2, 2)));
  run_podium({"run"}, dir.path());
  auto s = Store::open(dir / "podium.db", Store::Access::read_only);
  const auto trials = s->trials(s->stages(id).at(0).id);
  ASSERT_EQ(trials.size(), 2u);
  for (const auto& t : trials) {
    SCOPED_TRACE("trial " + std::to_string(t.index));
    EXPECT_EQ(t.state, "failed");
    EXPECT_EQ(t.attempts, 1);
    EXPECT_NE(t.error.find("probe: rejects its input (not retried: the task rejected its input)"), std::string::npos) << t.error;
  }
}

// A trial whose first attempt ran in a folder already in use (a reused run_dir) starts empty.
TEST(TrialResume, AFirstAttemptStartsInAnEmptyFolder) {
  TempDir dir;
  Json spec = probe_campaign({{"steps", 2}}, 1, 0);
  spec["run_dir"] = (dir / "runs").string();
  std::filesystem::create_directories(dir / "runs/stage-0-train/trial-0");
  podium::testing::write_file(dir / "runs/stage-0-train/trial-0/checkpoint.json", R"({"step": 2})");
  const auto id = std::stoll(podium::testing::submit_spec(dir.path(), spec));
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  auto s = Store::open(dir / "podium.db", Store::Access::read_only);
  const auto t = s->trials(s->stages(id).at(0).id).at(0);
  EXPECT_EQ(t.result_info["resumed_from_step"], 0);
  EXPECT_EQ(s->metrics(t.id).size(), 2u);
}

// The number of the campaign's attempt now running, or 0.
int running_attempt(const TempDir& dir, std::int64_t id) {
  auto s = Store::open(dir / "podium.db", Store::Access::read_only);
  const auto running = s->running_attempts(s->stages(id).at(0).id);
  return running.empty() ? 0 : running.front().number;
}

// `retries` counts attempts that failed, not those a stopped scheduler interrupted: a trial whose
// scheduler was killed twice under it still has its one retry when its third attempt fails.
TEST(TrialResume, AnAttemptInterruptedByAStoppedSchedulerDoesNotUseUpARetry) {
  TempDir dir;
  const auto id = std::stoll(podium::testing::submit_spec(
      dir.path(), probe_campaign({{"steps", 1}, {"sleep_s", 3.0}, {"fail_step", 0}, {"fail_attempts", 3}}, 1, 1)));
  for (int attempt = 1; attempt <= 2; ++attempt) {
    const pid_t pid = podium::testing::spawn_podium({"run"}, dir.path());
    // Killed as soon as the store says the attempt runs: well inside the 3 s before the probe fails it.
    ASSERT_TRUE(podium::testing::wait_until(
        pid, [&] { return running_attempt(dir, id) == attempt; }, 20.0));
    ::kill(pid, SIGKILL);
    podium::testing::wait_process(pid);
  }
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  auto s = Store::open(dir / "podium.db", Store::Access::read_only);
  const auto t = s->trials(s->stages(id).at(0).id).at(0);
  EXPECT_EQ(t.state, "done") << t.error;
  std::vector<std::string> states;
  for (const auto& a : s->attempts(t.id)) states.push_back(a.state);
  EXPECT_EQ(states, (std::vector<std::string>{"interrupted", "interrupted", "failed", "done"}));
  EXPECT_EQ(t.result_info["previous_attempt"]["number"], 3);
}

}  // namespace
}  // namespace podium::orchestrator
