// The Slurm executor against a real single-node Slurm cluster started by slurm_cluster.sh (needs
// root, slurm-wlm and munge; skipped with the script's reason where they are missing).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/run_folders.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;
using podium::testing::write_file;

const std::string kClusterScript = std::string(PODIUM_SOURCE_DIR) + "/tests/orchestrator/slurm_cluster.sh";
const std::string kClusterState = "/tmp/podium-slurm-test";

std::string shell(const std::string& command) { return podium::testing::shell(command).out; }

class Slurm : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string out = shell(kClusterScript + " start " + kClusterState + " 2>&1");
    const auto ready = out.find("ready: SLURM_CONF=");
    if (ready == std::string::npos) {
      skip_reason_ = out.empty() ? "the cluster script printed nothing" : out.substr(0, out.find('\n'));
      return;
    }
    std::string conf = out.substr(ready + 18);
    conf = conf.substr(0, conf.find('\n'));
    ::setenv("SLURM_CONF", conf.c_str(), 1);
  }
  static void TearDownTestSuite() { shell(kClusterScript + " stop " + kClusterState); }
  void SetUp() override {
    if (!skip_reason_.empty()) GTEST_SKIP() << "Slurm tests skipped: " << skip_reason_;
  }
  static std::string skip_reason_;
};
std::string Slurm::skip_reason_;

Json spec_for(const std::string& executor, int trials, const Json& config, int workers = 8, const Json& extra = {}) {
  Json exec = {{"kind", executor}};
  if (executor == "slurm") {
    exec["partition"] = "debug";
    exec["max_jobs_in_queue"] = workers;
    for (const auto& [k, v] : extra.items()) exec[k] = v;
  }
  return podium::testing::stage_spec({.name = "slurm-test",
                                      .seed = 5,
                                      .workers = workers,
                                      .trial_timeout_s = 300,
                                      .config = config,
                                      .executor = exec,
                                      .trials = trials});
}

std::string submit(const TempDir& dir, const Json& spec) { return podium::testing::submit_spec(dir.path(), spec); }

std::set<std::string> results(const TempDir& dir, const std::string& id) {
  const auto r = run_podium({"export", id, "--format", "json"}, dir.path());
  std::set<std::string> out;
  for (const auto& row : Json::parse(r.out))
    out.insert(Json{row["trial"], row["params"], row["objectives"], row["features"], row["state"]}.dump());
  return out;
}

TEST_F(Slurm, CampaignResultsMatchTheLocalExecutor) {
  TempDir local, cluster;
  const auto local_id = submit(local, spec_for("local", 50, Json::object(), 2));
  ASSERT_EQ(run_podium({"run"}, local.path()).exit_code, 0);
  const auto id = submit(cluster, spec_for("slurm", 50, Json::object()));
  const auto run = run_podium({"run"}, cluster.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(results(cluster, id), results(local, local_id));

  auto store = store::Store::open(cluster / "podium.db", store::Store::Access::read_only);
  const auto trials = store->campaign_trials(std::stoll(id));
  ASSERT_EQ(trials.size(), 50u);
  const auto attempts = store->attempts(trials[7].id);
  ASSERT_EQ(attempts.size(), 1u);
  EXPECT_FALSE(attempts[0].job_id.empty());
  EXPECT_NE(attempts[0].job_id.find('_'), std::string::npos) << "expected a job-array element id";
  EXPECT_EQ(store->metrics(trials[7].id).size(), 5u);  // streamed through metrics.jsonl
}

// The hand-over and the previous attempt reach `podium trial` in a job as they reach a local
// worker, and a retried job resumes in the trial folder (the probe task reports all three).
TEST_F(Slurm, HandOverAndResumeReachJobsAsTheyReachLocalWorkers) {
  auto probe_spec = [](const std::string& executor) {
    Json spec = spec_for(executor, 3, Json::object(), 4);
    spec["stages"][0]["task"] = "probe";
    spec["stages"][0].erase("preset");
    spec["stages"][0]["config"] = {{"steps", 6}, {"fail_step", 3}, {"fail_attempts", 1}};
    spec["stages"].push_back({{"name", "each"},
                              {"task", "probe"},
                              {"search", {{"algorithm", "random"}}},
                              {"budget", {{"trials", {{"per_input", 1}}}}},
                              {"inputs", {{"stage", "explore"}, {"select", "top"}, {"k", 2}, {"per_trial", "each"}}}});
    return spec;
  };
  auto seen = [](const TempDir& dir, const std::string& id) {
    auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
    const auto run_dir = store::campaign_run_dir(dir / "podium.db", *store->campaign(std::stoll(id)));
    const auto stages = store->stages(std::stoll(id));
    std::set<std::string> out;
    for (const auto& t : store->campaign_trials(std::stoll(id))) {
      // The trial's log, each attempt's header without its time: a job writes it as a worker does.
      const auto stage = std::find_if(stages.begin(), stages.end(), [&](const auto& st) { return st.id == t.stage_id; });
      std::istringstream log(podium::testing::file_bytes(store::trial_folder(run_dir, *stage, t.index) / store::kTrialLog));
      Json log_lines = Json::array();
      for (std::string line; std::getline(log, line);) log_lines.push_back(line.substr(0, line.find(" started ")));
      EXPECT_GE(log_lines.size(), 2u) << "trial " << t.index << ": no header and probe line in its log";
      Json inputs = Json::array();
      for (const auto& in : t.result_info["inputs"])
        inputs.push_back({in["stage"], in["trial_index"], in["artifacts"]["policy"]["exists"]});
      Json steps = Json::array();
      for (const auto& m : store->metrics(t.id)) steps.push_back({m.step, m.attempt});
      const Json& previous = t.result_info["previous_attempt"];
      out.insert(Json{t.index, t.state, t.objectives, inputs, previous.is_null() ? Json() : previous["state"],
                      t.result_info["resumed_from_step"], steps, log_lines}
                     .dump());
    }
    return out;
  };
  TempDir local, cluster;
  const auto local_id = submit(local, probe_spec("local"));
  ASSERT_EQ(run_podium({"run"}, local.path()).exit_code, 0);
  const auto id = submit(cluster, probe_spec("slurm"));
  const auto run = run_podium({"run"}, cluster.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto expected = seen(local, local_id);
  EXPECT_EQ(seen(cluster, id), expected);
  EXPECT_EQ(expected.size(), 5u);
}

TEST_F(Slurm, KilledSchedulerReattachesToRunningJobs) {
  TempDir dir;
  const auto id = submit(dir, spec_for("slurm", 4, {{"sleep_s", 6.0}}, 4));
  const pid_t scheduler = podium::testing::spawn_podium({"run"}, dir.path());
  // Wait until every attempt is placed in Slurm, then kill the scheduler mid-run.
  bool placed = false;
  for (int i = 0; i < 100 && !placed; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const std::string n = shell("sqlite3 " + (dir / "podium.db").string() +
                                " \"SELECT count(*) FROM attempts WHERE job_id != '' AND state = 'running'\" 2>/dev/null");
    placed = std::atoi(n.c_str()) == 4;
  }
  ASSERT_TRUE(placed);
  ::kill(scheduler, SIGKILL);
  podium::testing::wait_process(scheduler);

  const auto run = run_podium({"run", "--log-json"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n') >= 4, true);
  EXPECT_NE(run.out.find("attempt_reattached"), std::string::npos) << run.out;
  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  for (const auto& t : store->campaign_trials(std::stoll(id))) {
    EXPECT_EQ(t.state, "done");
    const auto attempts = store->attempts(t.id);
    ASSERT_EQ(attempts.size(), 1u) << "trial " << t.index << " was resubmitted";
    EXPECT_EQ(attempts[0].state, "done");
  }
}

TEST_F(Slurm, ScancelAndTimeLimitAreRecordedAndRetried) {
  // Trial 0 hangs past the job time limit (1 minute); trial 1 hangs until this test scancels it.
  const Json failures = Json::parse(R"([{"mode": "hang", "trials": [0, 1], "attempts": 1}])");
  TempDir dir;
  const auto id = submit(dir, spec_for("slurm", 3, {{"failures", failures}}, 4, {{"time", "1"}}));
  const pid_t scheduler = podium::testing::spawn_podium({"run"}, dir.path());
  std::string job;
  for (int i = 0; i < 200 && job.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    job = shell("sqlite3 " + (dir / "podium.db").string() +
                " \"SELECT a.job_id FROM attempts a JOIN trials t ON t.id = a.trial_id WHERE t.idx = 1 AND a.job_id != ''"
                " AND a.host != ''\" 2>/dev/null");  // the host is known once the job runs
    job = job.substr(0, job.find('\n'));
  }
  ASSERT_FALSE(job.empty());
  shell("scancel " + job);
  ASSERT_EQ(podium::testing::wait_process(scheduler), 0);

  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  const auto trials = store->campaign_trials(std::stoll(id));
  ASSERT_EQ(trials.size(), 3u);
  const auto timed_out = store->attempts(trials[0].id);
  ASSERT_EQ(timed_out.size(), 2u);
  EXPECT_EQ(timed_out[0].state, "timeout");
  EXPECT_NE(timed_out[0].error.find("TIMEOUT"), std::string::npos) << timed_out[0].error;
  const auto cancelled = store->attempts(trials[1].id);
  ASSERT_EQ(cancelled.size(), 2u);
  EXPECT_EQ(cancelled[0].state, "failed");
  EXPECT_NE(cancelled[0].error.find("CANCELLED"), std::string::npos) << cancelled[0].error;
  for (const auto& t : trials) EXPECT_EQ(t.state, "done") << t.index;
}

// The get-up campaign as a cluster run would take it (the next step: more seeds, more
// steps): the shipped campaigns/getup.json put on Slurm by `submit --set`, at the smoke preset,
// with a third Weaker seed, and Weaker's wall-clock limit (learn::WallBudget) set so it ends
// training after the first round: the limit lives in the trial, so it holds inside a job too.
TEST_F(Slurm, TheShippedGetupCampaignRunsOnSlurmAsEditedBySubmitSet) {
  TempDir dir;
  std::vector<std::string> submit_args = {"submit", std::string(PODIUM_SOURCE_DIR) + "/campaigns/getup.json",
                                          "--set",  R"(executor={"kind": "slurm", "partition": "debug", "max_jobs_in_queue": 4})",
                                          "--set",  "trial_timeout_s=300",
                                          "--set",  "stages[0].budget.trials=3",
                                          "--set",  "stages[0].config.train_minutes=1e-9"};
  for (int stage = 0; stage < 3; ++stage)
    submit_args.insert(submit_args.end(), {"--set", "stages[" + std::to_string(stage) + "].preset=smoke"});
  const auto submitted = run_podium(submit_args, dir.path());
  ASSERT_EQ(submitted.exit_code, 0) << submitted.err;
  const auto run = run_podium({"run"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;

  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  std::map<std::string, int> done;
  for (const auto& stage : store->stages(1))
    for (const auto& t : store->trials(stage.id)) {
      EXPECT_EQ(t.state, "done") << stage.name << "/" << t.index;
      done[stage.name] += t.state == "done";
      const auto attempts = store->attempts(t.id);
      ASSERT_FALSE(attempts.empty());
      EXPECT_FALSE(attempts.back().job_id.empty()) << stage.name << "/" << t.index << " did not run in a Slurm job";
      if (stage.name != "weaker") continue;
      EXPECT_EQ(t.result_info["stopped_by"], "time") << t.result_info.dump();
      EXPECT_EQ(t.result_info["env_steps"], 100);  // one round of the smoke preset's 400 steps
    }
  EXPECT_EQ(done, (std::map<std::string, int>{{"weaker", 3}, {"slower", 3}, {"evaluate", 3}}));
}

TEST_F(Slurm, BadSpecIsOneLineBeforeAnythingIsQueued) {
  TempDir dir;
  Json spec = spec_for("slurm", 2, Json::object());
  spec["executor"]["partition"] = "gpu-nonexistent";
  write_file(dir / "spec.json", spec.dump());
  auto r = run_podium({"submit", "spec.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("executor.partition: \"gpu-nonexistent\" is not a partition of this cluster (sinfo lists: debug"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);

  const std::string path = std::getenv("PATH");
  ::setenv("PATH", "/nonexistent", 1);
  write_file(dir / "spec.json", spec_for("slurm", 2, Json::object()).dump());
  r = run_podium({"submit", "spec.json"}, dir.path());
  ::setenv("PATH", path.c_str(), 1);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("executor.kind: \"slurm\" needs sbatch, which is not on PATH"), std::string::npos) << r.err;

  const auto status = run_podium({"status", "--json"}, dir.path());
  EXPECT_TRUE(status.exit_code != 0 || Json::parse(status.out).empty()) << "nothing may be queued";
}

}  // namespace
}  // namespace podium::orchestrator
