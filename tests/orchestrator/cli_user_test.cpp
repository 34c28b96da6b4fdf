// What a new user met: trial names and the trials table, a reused campaign name, and
// extending a finished campaign. Real `podium` processes, a real SQLite file, the landscape plugin.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;

Json one_stage(const std::string& name, const std::string& algorithm, int trials, const Json& config = Json::object()) {
  return podium::testing::stage_spec({.name = name,
                                      .seed = 5,
                                      .workers = 1,
                                      .retries = 0,
                                      .trial_timeout_s = 60,
                                      .algorithm = algorithm,
                                      .config = config,
                                      .trials = trials});
}

std::string submit(const TempDir& dir, const Json& spec) { return podium::testing::submit_spec(dir.path(), spec); }

void run_all(const TempDir& dir) {
  const auto r = run_podium({"run", "--workers", "1"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

Json export_json(const TempDir& dir, const std::string& campaign) {
  const auto r = run_podium({"export", campaign, "--format", "json"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return Json::parse(r.out);
}

std::string significant(double value, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(CliUser, TrialsTableNamesTrialsByStageAndIndexWithReadableNumbers) {
  TempDir dir;
  const Json config = {{"failures", Json::array({{{"mode", "throw"}, {"trials", {2}}}})}};
  const auto id = submit(dir, one_stage("table", "random", 5, config));
  run_all(dir);
  const auto rows = export_json(dir, id);
  ASSERT_EQ(rows.size(), 5u);

  const auto r = run_podium({"trials", id}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto table = lines(r.out);
  ASSERT_EQ(table.size(), 6u) << r.out;
  EXPECT_EQ(words(table[0]),
            (std::vector<std::string>{"trial", "state", "attempts", "objective", "strategy", "id", "f0", "f1", "error"}));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Json& row = rows[i];
    SCOPED_TRACE(table[i + 1]);
    const auto cells = words(table[i + 1]);
    ASSERT_GE(cells.size(), 7u);
    EXPECT_EQ(cells[0], "explore/" + std::to_string(row["trial"].get<int>()));
    EXPECT_EQ(cells[1], row["state"]);
    EXPECT_EQ(cells[5], std::to_string(row["id"].get<std::int64_t>()));  // the dashboard's trial.html?id=
    if (row["state"] == "done") {
      EXPECT_EQ(cells[3], significant(row["objectives"]["objective"].get<double>(), 4));
      EXPECT_EQ(cells[4], std::to_string(row["strategy_label"].get<int>()));  // what users read, not the grid cell
      EXPECT_EQ(cells[6], significant(row["features"]["f0"].get<double>(), 3));
      EXPECT_EQ(cells[7], significant(row["features"]["f1"].get<double>(), 3));
    } else {
      EXPECT_EQ(row["trial"], 2);
      EXPECT_EQ(cells[3], "-");
      EXPECT_EQ(cells[4], "-");
      EXPECT_NE(table[i + 1].find(row["error"].get<std::string>()), std::string::npos);
    }
  }

  // --json: the same trials at full precision, each with its name and database id.
  const auto j = run_podium({"trials", id, "--json"}, dir.path());
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const Json full = Json::parse(j.out);
  ASSERT_EQ(full.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(full[i]["name"], "explore/" + std::to_string(rows[i]["trial"].get<int>()));
    EXPECT_EQ(full[i]["id"], rows[i]["id"]);
    EXPECT_EQ(full[i]["objectives"], rows[i]["objectives"]);  // the stored doubles, not 4 digits
  }
}

// `podium log` prints what a trial's attempts wrote (the local executor's trial.log): a header per
// attempt, and for a failed one the reason as its last line; --tail and --path; a wrong name is a
// one-line error.
TEST(CliUser, LogPrintsWhatATrialsAttemptsWrote) {
  TempDir dir;
  const Json config = {{"failures", Json::array({{{"mode", "throw"}, {"trials", {1}}}})}};
  const auto id = submit(dir, one_stage("logs", "random", 2, config));
  run_all(dir);

  const auto done = run_podium({"log", "logs", "explore/0"}, dir.path());
  ASSERT_EQ(done.exit_code, 0) << done.err;
  EXPECT_EQ(done.out.rfind("podium: attempt 1 started ", 0), 0u) << done.out;
  EXPECT_EQ(done.out.find("attempt failed"), std::string::npos) << done.out;

  const auto failed = run_podium({"log", id, "explore/1"}, dir.path());
  ASSERT_EQ(failed.exit_code, 0) << failed.err;
  const auto failed_lines = lines(failed.out);
  ASSERT_GE(failed_lines.size(), 2u) << failed.out;
  EXPECT_EQ(failed_lines[0].rfind("podium: attempt 1 started ", 0), 0u) << failed.out;
  EXPECT_NE(failed_lines.back().find("attempt failed"), std::string::npos) << failed.out;

  const auto tail = run_podium({"log", id, "explore/1", "--tail", "1"}, dir.path());
  ASSERT_EQ(tail.exit_code, 0) << tail.err;
  EXPECT_EQ(lines(tail.out), std::vector<std::string>{failed_lines.back()});

  const auto path = run_podium({"log", id, "explore/1", "--path"}, dir.path());
  ASSERT_EQ(path.exit_code, 0) << path.err;
  EXPECT_EQ(podium::testing::file_bytes(lines(path.out).at(0)), failed.out);

  for (const std::string wrong : {"explore/2", "explore", "nosuch/0", "explore/-1"}) {
    const auto r = run_podium({"log", id, wrong}, dir.path());
    EXPECT_EQ(r.exit_code, 2) << wrong;
    EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("no trial \"" + wrong + "\""), std::string::npos) << r.err;
  }
}

TEST(CliUser, StatusNamesARunningAttemptsTrialTheSameWay) {
  TempDir dir;
  const Json hang = {{"failures", Json::array({{{"mode", "hang"}, {"trials", {0}}, {"attempts", 1}}})}};
  const auto id = submit(dir, one_stage("named", "random", 2, hang));
  const pid_t scheduler = podium::testing::spawn_podium({"run", "--workers", "1"}, dir.path());
  for (;;) {  // until trial 0's first attempt runs (it hangs), or the scheduler has exited
    if (store::Store::open(dir / "podium.db", store::Store::Access::read_only)->trial_counts(1).running > 0) break;
    ASSERT_NE(::waitpid(scheduler, nullptr, WNOHANG), scheduler) << "the scheduler exited before trial 0 ran";
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(scheduler, SIGKILL);  // its worker goes with it (PR_SET_PDEATHSIG)
  podium::testing::wait_process(scheduler);
  const auto r = run_podium({"status", id}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\n    trial explore/0 attempt 1 on .*: interrupted, its scheduler is gone\n")))
      << r.out;
  const auto j = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(j["stages"][0]["running_attempts"][0]["name"], "explore/0");
}

TEST(CliUser, ASecondSubmitOfANameSaysWhichCampaignTheNameNowMeans) {
  TempDir dir;
  const Json spec = one_stage("twice", "random", 3);
  podium::testing::write_file(dir / "spec.json", spec.dump());
  const auto first = run_podium({"submit", "spec.json"}, dir.path());
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(first.out, "1\n");
  EXPECT_EQ(first.err, "");
  const auto second = run_podium({"submit", "spec.json"}, dir.path());
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(second.out, "2\n");
  EXPECT_EQ(second.err,
            "podium: note: campaign 2 has the name \"twice\" of campaign 1; a CAMPAIGN name means the newest campaign "
            "of that name, so \"twice\" is now campaign 2 (the older stay reachable by id)\n");
  const auto status = run_podium({"status", "twice", "--json"}, dir.path());
  ASSERT_EQ(status.exit_code, 0) << status.err;
  EXPECT_EQ(Json::parse(status.out)["id"], 2);
  const auto third = run_podium({"submit", "spec.json"}, dir.path());
  EXPECT_NE(third.err.find("campaign 3 has the name \"twice\" of campaign 1, 2;"), std::string::npos) << third.err;
}

// `--set` makes a variant of a spec file in one command (get-up variants once took a `sed`):
// the edited spec is the one checked, by the validator and the task, and the one stored.
TEST(CliUser, SubmitSetEditsTheSpecBeforeItIsCheckedAndStored) {
  TempDir dir;
  podium::testing::write_file(dir / "spec.json", one_stage("base", "random", 3).dump());
  const auto ok = run_podium({"submit", "spec.json", "--set", "seed=77", "--set", "stages[0].budget.trials=5", "--set",
                              "name=variant", "--set", "stages[0].config.noise=0.25"},
                             dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto status = Json::parse(run_podium({"status", "variant", "--json"}, dir.path()).out);
  EXPECT_EQ(status["seed"], 77);
  EXPECT_EQ(status["budget_trials"], 5);
  {
    const auto store = podium::store::Store::open(dir / "podium.db", podium::store::Store::Access::read_only);
    EXPECT_EQ(store->campaign(1)->spec["stages"][0]["config"]["noise"], 0.25);
    EXPECT_EQ(store->stages(1).at(0).task_config["noise"], 0.25);  // what the trials are given
  }

  auto expect_refused = [&](const std::string& edit, const std::string& pattern) {
    const auto r = run_podium({"submit", "spec.json", "--set", edit}, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(std::regex_search(r.err, std::regex(pattern))) << edit << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  expect_refused("stages[1].budget.trials=1", "^podium: --set stages\\[1\\]\\.budget\\.trials=1: stages has 1 items, no \\[1\\]");
  expect_refused("seed.x=1", "^podium: --set seed\\.x=1: seed is not an object");
  expect_refused("seed", "^podium: --set seed: no '='");
  expect_refused("stages[x]=1", "is not an array index like \\[0\\]");
  // The task names the key it does not know, in the spec as edited.
  expect_refused("stages[0].config.bogus=1", "^podium: spec\\.json as edited by --set: stages\\[0\\]\\.config\\.bogus");
  expect_refused("seed=\"many\"", "^podium: spec\\.json as edited by --set: seed");
  // Nothing refused was queued.
  const auto all = Json::parse(run_podium({"status", "--json"}, dir.path()).out);
  EXPECT_EQ(all.size(), 1u) << all.dump();
}

// A nested key set over a preset changes that key only: the style-curve get-up's quick preset
// carries a whole PPO object, and `--set ...ppo.lr_anneal_steps` keeps its other keys.
TEST(CliUser, ANestedConfigKeyIsMergedOverThePresetKeyByKey) {
  TempDir dir;
  Json spec = one_stage("nested", "random", 1);
  spec["stages"][0]["task"] = "getup_curves";
  spec["stages"][0]["preset"] = "quick";
  spec["stages"][0]["config"] = {{"stage", "train"}};
  podium::testing::write_file(dir / "spec.json", spec.dump());
  const auto ok = run_podium({"submit", "spec.json", "--set", "stages[0].config.ppo.lr_anneal_steps=5000000"}, dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto store = podium::store::Store::open(dir / "podium.db", podium::store::Store::Access::read_only);
  const Json ppo = store->stages(1).at(0).task_config.at("ppo");
  EXPECT_EQ(ppo["lr_anneal_steps"], 5000000);
  EXPECT_EQ(ppo["hidden"], Json({256, 256})) << ppo;  // the preset's, kept
  EXPECT_EQ(ppo["sigma_anneal_steps"], 2200000) << ppo;
}

// The trials of a campaign as (index, params, objectives, features, strategy, state).
std::vector<std::string> results(const TempDir& dir, const std::string& id) {
  std::vector<std::string> out;
  for (const auto& row : export_json(dir, id))
    out.push_back(Json{row["trial"], row["params"], row["objectives"], row["features"], row["strategy"], row["state"]}.dump());
  return out;
}

TEST(CliUser, ExtendContinuesTheSearchAsALargerBudgetWouldHave) {
  TempDir extended, fresh;
  const auto id = submit(extended, one_stage("grow", "bds", 8));
  run_all(extended);
  const auto e = run_podium({"extend", "grow", "--stage", "explore", "--add-trials", "6"}, extended.path());
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_EQ(e.out, "campaign " + id +
                       " (grow) stage \"explore\": budget raised from 8 to 14 trials; queued again: podium run "
                       "continues its search where it stopped\n");
  const auto queued = Json::parse(run_podium({"status", id, "--json"}, extended.path()).out);
  EXPECT_EQ(queued["state"], "queued");
  EXPECT_EQ(queued["budget_trials"], 14);
  EXPECT_EQ(queued["done"], 8);
  run_all(extended);

  const auto fresh_id = submit(fresh, one_stage("grow", "bds", 14));
  run_all(fresh);
  const auto a = results(extended, id), b = results(fresh, fresh_id);
  ASSERT_EQ(a.size(), 14u);
  ASSERT_EQ(b.size(), 14u);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "trial " << i;
  const auto done = Json::parse(run_podium({"status", id, "--json"}, extended.path()).out);
  EXPECT_EQ(done["state"], "done");
  EXPECT_EQ(done["done"], 14);
}

TEST(CliUser, ExtendRefusesWhatItCannotContinueInOneLine) {
  TempDir dir;
  auto expect_refused = [&](const std::vector<std::string>& args, const std::string& pattern) {
    const auto r = run_podium(args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(std::regex_search(r.err, std::regex(pattern))) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  expect_refused({"extend", "x", "--add-trials", "1"}, "^podium: podium.db: no such database");
  Json two = one_stage("two", "random", 2);
  two["stages"].push_back(two["stages"][0]);
  two["stages"][1]["name"] = "refine";
  const auto id = submit(dir, two);
  expect_refused({"extend", id, "--add-trials", "1"},
                 "^podium: campaign 1 \\(two\\) is queued: extend continues a done campaign \\(let it finish");
  run_all(dir);
  expect_refused({"extend", id, "--stage", "explore", "--add-trials", "1"},
                 "stage \"explore\" of campaign 1 \\(two\\) is followed by stages that have run \\(explore, refine\\): "
                 "only the last stage, \"refine\", can be extended");
  expect_refused({"extend", id, "--stage", "nope", "--add-trials", "1"}, "has no stage \"nope\" \\(stages: explore, refine\\)");
  expect_refused({"extend", id, "--add-trials=0"}, "--add-trials: 0 is not in \\[1, 9999998\\]");
  expect_refused({"extend", id, "--add-trials", "9999999"}, "--add-trials: 9999999 is not in \\[1, 9999998\\]");
  expect_refused({"extend", id}, "^podium extend: .*add-trials.* \\(see podium extend --help\\)");
  expect_refused({"extend", "nobody", "--add-trials", "1"}, "^podium: no campaign \"nobody\"");
  // Nothing refused changed the campaign.
  const auto status = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(status["state"], "done");
  EXPECT_EQ(status["budget_trials"], 4);
  const auto ok = run_podium({"extend", id, "--add-trials", "3"}, dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("stage \"refine\": budget raised from 2 to 5 trials"), std::string::npos) << ok.out;
  run_all(dir);
  const auto after = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(after["done"], 7);
  EXPECT_EQ(after["stages"][0]["done"], 2);  // the first stage ran nothing again
}

}  // namespace
}  // namespace podium::orchestrator
