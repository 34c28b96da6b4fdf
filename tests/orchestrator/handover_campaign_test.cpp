// The hand-over acceptance campaigns on the test_pendulum task (PPO on learn's Pendulum; real
// `podium submit` / `podium run` processes, a real SQLite file): a three-stage hand-over whose
// later stages warm-start from the earlier stages' policies, and the same campaign with its
// scheduler SIGKILLed mid-training, which must end exactly as the uninterrupted one.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>

#include <fstream>
#include <map>
#include <memory>
#include <set>

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

constexpr int kExploreTrials = 4;

// explore: random over the learning rate; refine: once per strategy of explore (its best trial),
// warm-started from that trial's policy; polish: from refine's best.
Json handover_spec() {
  const Json smoke = {{"updates", 30}, {"checkpoint_every", 3}};
  const auto stage = [&](const std::string& name) {
    return Json{
        {"name", name}, {"task", "test_pendulum"}, {"preset", "smoke"}, {"config", smoke}, {"search", {{"algorithm", "random"}}}};
  };
  Json explore = stage("explore"), refine = stage("refine"), polish = stage("polish");
  explore["budget"] = {{"trials", kExploreTrials}};
  refine["budget"] = {{"trials", {{"per_input", 1}}}};
  refine["inputs"] = {{"stage", "explore"}, {"select", "best_per_strategy"}, {"per_trial", "each"}};
  polish["budget"] = {{"trials", 2}};
  polish["inputs"] = {{"stage", "refine"}, {"select", "best"}};
  return {{"name", "pendulum_handover"},        {"seed", 16}, {"workers", 2}, {"retries", 3}, {"trial_timeout_s", 300},
          {"stages", {explore, refine, polish}}};
}

// Everything a finished campaign's trial leaves that a resumed run must reproduce.
struct TrialOutcome {
  store::TrialRecord trial;
  std::map<std::pair<std::string, double>, double> metrics;  // (name, step) -> value; time/: 0
  std::map<std::string, std::string> artifact_sha256;
};

// (stage index, trial index) -> outcome.
using Outcomes = std::map<std::pair<int, std::int64_t>, TrialOutcome>;

Outcomes outcomes(const TempDir& dir, const std::string& id) {
  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  Outcomes out;
  for (const auto& stage : store->stages(std::stoll(id)))
    for (const auto& t : store->trials(stage.id)) {
      TrialOutcome o{t, {}, {}};
      // The time/ series are wall seconds, different in every run: their names and steps count.
      for (const auto& m : store->metrics(t.id)) o.metrics[{m.name, m.step}] = m.name.rfind("time/", 0) == 0 ? 0.0 : m.value;
      for (const auto& a : store->artifacts(t.id)) o.artifact_sha256[a.name] = a.sha256;
      out[{stage.index, t.index}] = std::move(o);
    }
  return out;
}

// One uninterrupted run of the campaign, shared by the tests.
struct Reference {
  TempDir dir;
  std::string id;
  Outcomes trials;
};

const Reference& reference() {
  static std::unique_ptr<Reference> ref;
  if (!ref) {
    ref = std::make_unique<Reference>();
    ref->id = podium::testing::submit_spec(ref->dir.path(), handover_spec());
    const auto run = run_podium({"run"}, ref->dir.path());
    EXPECT_EQ(run.exit_code, 0) << run.err;
    ref->trials = outcomes(ref->dir, ref->id);
  }
  return *ref;
}

// One SQL count on the database the scheduler is writing (read-only, its own connection).
std::int64_t count(const std::filesystem::path& db, const std::string& sql) {
  sqlite3* handle = nullptr;
  std::int64_t n = -1;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(handle, 2000);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(handle, sql.c_str(), -1, &statement, nullptr) == SQLITE_OK && sqlite3_step(statement) == SQLITE_ROW)
      n = sqlite3_column_int64(statement, 0);
    sqlite3_finalize(statement);
  }
  sqlite3_close(handle);
  return n;
}

const std::string kExploreMetrics =
    "SELECT COUNT(*) FROM metrics m JOIN trials t ON t.id = m.trial_id JOIN stages s ON s.id = t.stage_id "
    "WHERE s.idx = 0";

TEST(HandoverCampaign, LaterStagesWarmStartFromTheirInputsPolicies) {
  const auto& ref = reference();
  auto store = store::Store::open(ref.dir / "podium.db", store::Store::Access::read_only);
  const auto stages = store->stages(std::stoll(ref.id));
  ASSERT_EQ(stages.size(), 3u);
  for (const auto& s : stages) EXPECT_EQ(s.state, "done") << s.name << ": " << s.error;
  EXPECT_EQ(store->campaign(std::stoll(ref.id))->state, "done");

  // refine: one trial per explore strategy, each from that strategy's best trial.
  std::map<std::int64_t, const store::TrialRecord*> best_of_strategy;
  for (const auto& [key, o] : ref.trials) {
    if (key.first != 0) continue;
    ASSERT_EQ(o.trial.state, "done") << "explore trial " << key.second << ": " << o.trial.error;
    ASSERT_TRUE(o.trial.strategy.has_value());
    auto& best = best_of_strategy[*o.trial.strategy];
    if (!best || o.trial.objectives[0].get<double>() > best->objectives[0].get<double>()) best = &o.trial;
  }
  EXPECT_GE(best_of_strategy.size(), 2u) << "explore found one strategy: the hand-over is not exercised";
  std::set<std::int64_t> expected_sources, sources;
  for (const auto& [strategy, t] : best_of_strategy) expected_sources.insert(t->index);

  // Checks a trial's warm start from stage `from_index`; returns the source trial's index (-1: none).
  const auto check_warm_start = [&](const TrialOutcome& o, const std::string& from_stage, int from_index) -> std::int64_t {
    const Json& info = o.trial.result_info;
    if (!info.is_object() || !info.contains("warm_start") || !info["warm_start"].is_object()) {
      ADD_FAILURE() << "trial " << o.trial.index << " did not warm-start: " << info;
      return -1;
    }
    EXPECT_EQ(info["warm_start"]["stage"], from_stage);
    const auto source_index = info["warm_start"]["trial_index"].get<std::int64_t>();
    const auto& source = ref.trials.at({from_index, source_index}).trial;
    // The first evaluation (before training) of the warm-started policy is the source's last.
    const double source_return = source.objectives[0].get<double>();
    EXPECT_NEAR(info["first_eval_return"].get<double>(), source_return, 1e-9) << "trial " << o.trial.index;
    EXPECT_NEAR(o.metrics.count({"eval_return", 0.0}) ? o.metrics.at({"eval_return", 0.0}) : 1e300, source_return, 1e-9)
        << "the metric eval_return at step 0";
    return source_index;
  };
  int refine_trials = 0, polish_trials = 0;
  for (const auto& [key, o] : ref.trials) {
    if (key.first == 0) continue;
    ASSERT_EQ(o.trial.state, "done") << "stage " << key.first << " trial " << key.second << ": " << o.trial.error;
    if (key.first == 1) {
      ++refine_trials;
      const auto source = check_warm_start(o, "explore", 0);
      sources.insert(source);
      // "each": trial i gets input i mod n of the inputs stored with the stage.
      const Json& inputs = stages[1].input_trials.value_or(Json::array());
      ASSERT_FALSE(inputs.empty()) << "refine has no stored inputs";
      EXPECT_EQ(inputs[static_cast<std::size_t>(key.second) % inputs.size()]["trial_index"], source)
          << "refine trial " << key.second;
    } else {
      ++polish_trials;
      // polish's input: refine's best trial.
      std::int64_t best = -1;
      double best_return = -1e300;
      for (const auto& [k, r] : ref.trials)
        if (k.first == 1 && r.trial.objectives[0].get<double>() > best_return) {
          best_return = r.trial.objectives[0].get<double>();
          best = k.second;
        }
      EXPECT_EQ(check_warm_start(o, "refine", 1), best);
    }
  }
  EXPECT_EQ(refine_trials, static_cast<int>(best_of_strategy.size()));
  EXPECT_EQ(sources, expected_sources) << "refine trials must start once from each strategy's best";
  EXPECT_EQ(polish_trials, 2);
}

TEST(HandoverCampaign, SchedulerKilledMidTrainingEndsAsTheUninterruptedRun) {
  const auto& ref = reference();
  std::int64_t explore_points = 0;
  for (const auto& [key, o] : ref.trials)
    if (key.first == 0) explore_points += static_cast<std::int64_t>(o.metrics.size());

  TempDir dir;
  const auto id = podium::testing::submit_spec(dir.path(), handover_spec());
  // Kill the scheduler and its workers when explore has stored 20%, 45% and 70% of its metric
  // points and some trial is part-way through training. A trial can end between a look at the
  // disk and a kill, so the processes are frozen first and the disk read while nothing moves.
  const auto explore_dir = dir / "podium.db.runs" / id / "stage-0-explore";
  const auto mid_training = [&] {  // trials with a checkpoint to resume from and no policy yet
    int n = 0;
    if (std::filesystem::exists(explore_dir))
      for (const auto& trial : std::filesystem::directory_iterator(explore_dir))
        n += std::filesystem::exists(trial.path() / "training.ckpt") && !std::filesystem::exists(trial.path() / "policy.pt");
    return n;
  };
  int kills = 0;
  for (const double share : {0.2, 0.45, 0.7}) {
    const pid_t pid = podium::testing::spawn_podium({"run"}, dir.path(), /*own_group=*/true);
    const auto target = static_cast<std::int64_t>(share * static_cast<double>(explore_points));
    bool frozen_mid_training = false;
    while (!frozen_mid_training &&
           podium::testing::wait_until(
               pid, [&] { return count(dir / "podium.db", kExploreMetrics) >= target && mid_training() >= 1; }, 180)) {
      podium::testing::freeze_group(pid);
      frozen_mid_training = mid_training() >= 1;
      if (!frozen_mid_training) ::killpg(pid, SIGCONT);
    }
    const bool exited = !frozen_mid_training && ::waitpid(pid, nullptr, WNOHANG) != 0;  // -1: wait_until reaped it
    if (!exited) {
      ::killpg(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    ASSERT_FALSE(exited) << "the scheduler ended before " << share * 100 << "% of explore's metric points";
    ASSERT_TRUE(frozen_mid_training) << "in 3 minutes explore neither stored " << share * 100
                                     << "% of its metric points nor had a trial part-way through training";
    ++kills;
    EXPECT_GE(mid_training(), 1) << "kill " << kills << " left no checkpoint of an unfinished trial";
  }
  const auto final_run = run_podium({"run"}, dir.path());
  ASSERT_EQ(final_run.exit_code, 0) << final_run.err;
  ASSERT_EQ(kills, 3);

  const auto resumed = outcomes(dir, id);
  ASSERT_EQ(resumed.size(), ref.trials.size());
  int interrupted = 0;
  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  for (const auto& [key, expected] : ref.trials) {
    const auto& got = resumed.at(key);
    const std::string where = "stage " + std::to_string(key.first) + " trial " + std::to_string(key.second);
    EXPECT_EQ(got.trial.state, "done") << where << ": " << got.trial.error;
    EXPECT_EQ(got.trial.params, expected.trial.params) << where;
    EXPECT_EQ(got.trial.objectives, expected.trial.objectives) << where;
    EXPECT_EQ(got.trial.features, expected.trial.features) << where;
    EXPECT_EQ(got.trial.result_info, expected.trial.result_info) << where << " (parameter_hash: the final policy)";
    EXPECT_EQ(got.artifact_sha256, expected.artifact_sha256) << where << " (the exported policy's bytes)";
    EXPECT_EQ(got.metrics, expected.metrics) << where << " (the metric series)";
    for (const auto& a : store->attempts(got.trial.id)) interrupted += key.first == 0 && a.state == "interrupted";
  }
  EXPECT_GE(interrupted, 3) << "the kills did not interrupt explore trials mid-training";
  // Each kill left an unfinished trial with a checkpoint; its next attempt says it resumed.
  int resumes = 0;
  for (const auto& trial : std::filesystem::directory_iterator(explore_dir)) {
    std::ifstream log(trial.path() / store::kTrialLog);
    for (std::string line; std::getline(log, line);) resumes += line.find("resumes after update") != std::string::npos;
  }
  EXPECT_GE(resumes, 3) << "fewer attempts resumed from a checkpoint than kills hit trials mid-training";
  EXPECT_EQ(
      count(dir / "podium.db", "SELECT COUNT(*) FROM (SELECT 1 FROM metrics GROUP BY trial_id, name, step HAVING COUNT(*) > 1)"),
      0)
      << "a metric point is stored twice";
}

}  // namespace
}  // namespace podium::orchestrator
