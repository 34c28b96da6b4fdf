// Same spec, same results: every algorithm's proposals are a function of the
// spec (seed, workers) alone, whatever the trials' durations and completion order. Real `podium
// run` on the landscape task: one run with a single worker process (trials finish in the order
// asked) against one with two (they finish in any order), and a run killed with SIGKILL twice.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <csignal>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;

Json one_stage(const std::string& algorithm, int trials, const Json& config) {
  return podium::testing::stage_spec({.name = "same-" + algorithm,
                                      .seed = 5,
                                      .workers = 2,
                                      .retries = 0,
                                      .trial_timeout_s = 60,
                                      .algorithm = algorithm,
                                      .config = config,
                                      .trials = trials});
}

// Every trial of the campaign: stage, index, parameters, objectives, features, state.
std::vector<std::string> results(const TempDir& dir, const std::string& id) {
  const auto r = run_podium({"export", id, "--format", "json"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> out;
  for (const auto& row : Json::parse(r.out))
    out.push_back(Json{row["stage"], row["trial"], row["params"], row["objectives"], row["features"], row["state"]}.dump());
  return out;
}

// How many trials differ (0 when both runs gave the same), with the first difference.
::testing::AssertionResult same_trials(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " vs " << b.size() << " trials";
  int differing = 0;
  std::string first;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i] && differing++ == 0) first = a[i] + "\n    vs " + b[i];
  if (differing == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << differing << " of " << a.size() << " trials differ; first:\n    " << first;
}

std::vector<std::string> run_with_workers(const Json& spec, int worker_processes) {
  TempDir dir;
  const auto id = podium::testing::submit_spec(dir.path(), spec);
  const auto r = run_podium({"run", "--workers", std::to_string(worker_processes)}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return results(dir, id);
}

TEST(Determinism, ProposalsDoNotDependOnHowManyWorkerProcessesRunTheTrials) {
  for (const std::string algorithm : {"random", "bds", "novelty", "cmaes"}) {
    SCOPED_TRACE(algorithm);
    const Json spec = one_stage(algorithm, 24, Json::object());
    const auto sequential = run_with_workers(spec, 1);
    ASSERT_EQ(sequential.size(), 24u);
    EXPECT_TRUE(same_trials(run_with_workers(spec, 2), sequential));
  }
}

// BDS, then novel-policy seeking from the best trial of each strategy it found.
TEST(Determinism, TheTwoStagePipelineGivesTheSameResultsWithOneOrTwoWorkerProcesses) {
  const Json spec = base::read_json_file(std::string(PODIUM_SOURCE_DIR) + "/campaigns/landscape_bds_novel_policy.json");
  const auto sequential = run_with_workers(spec, 1);
  ASSERT_GT(sequential.size(), 20u);
  EXPECT_TRUE(same_trials(run_with_workers(spec, 2), sequential));
}

// Waits (polling the store) until the campaign has `done` finished trials, or `pid` has exited.
void wait_for_done(const TempDir& dir, std::int64_t id, std::int64_t done, pid_t pid) {
  podium::testing::wait_until(
      pid, [&] { return store::Store::open(dir / "podium.db", store::Store::Access::read_only)->trial_counts(id).done >= done; });
}

TEST(Determinism, KillNineAndResumeWithTwoWorkersGivesTheUninterruptedResults) {
  const Json spec = one_stage("bds", 36, {{"sleep_s", 0.02}});
  TempDir reference;
  const auto ref_id = podium::testing::submit_spec(reference.path(), spec);
  ASSERT_EQ(run_podium({"run"}, reference.path()).exit_code, 0);

  TempDir dir;
  const auto id = podium::testing::submit_spec(dir.path(), spec);
  for (const std::int64_t done : {6, 18}) {
    const pid_t pid = podium::testing::spawn_podium({"run"}, dir.path());
    wait_for_done(dir, std::stoll(id), done, pid);
    ::kill(pid, SIGKILL);  // a no-op if it has finished: the comparison below holds either way
    ::waitpid(pid, nullptr, 0);
  }
  const auto last = run_podium({"run"}, dir.path());
  ASSERT_EQ(last.exit_code, 0) << last.err;
  EXPECT_TRUE(same_trials(results(dir, id), results(reference, ref_id)));
}

}  // namespace
}  // namespace podium::orchestrator
