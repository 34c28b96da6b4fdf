// End-to-end tests of the `podium` CLI: real processes, a real SQLite file, the landscape plugin.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/base/rng.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::file_bytes;
using podium::testing::run_podium;
using podium::testing::TempDir;
using podium::testing::write_file;

// The CLI tests' campaign: random search over the smoke landscape.
Json landscape_spec(int trials, const Json& config = Json::object(), int retries = 1, double timeout_s = 30) {
  return podium::testing::stage_spec({.retries = retries, .trial_timeout_s = timeout_s, .config = config, .trials = trials});
}

std::string submit(const TempDir& dir, const Json& spec) { return podium::testing::submit_spec(dir.path(), spec); }

Json export_json(const TempDir& dir, const std::string& campaign) {
  const auto r = run_podium({"export", campaign, "--format", "json"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return Json::parse(r.out);
}

TEST(Cli, Runs200TrialCampaignEndToEnd) {
  TempDir dir;
  const auto id = submit(dir, landscape_spec(200));
  const auto run = run_podium({"run", "--workers", "2"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const auto rows = export_json(dir, id);
  ASSERT_EQ(rows.size(), 200u);
  std::set<std::int64_t> indices, strategies;
  for (const auto& row : rows) {
    EXPECT_EQ(row["state"], "done");
    ASSERT_TRUE(row["strategy"].is_number()) << row;
    strategies.insert(row["strategy"].get<std::int64_t>());
    EXPECT_EQ(row["params"].size(), 3u);
    EXPECT_EQ(row["features"].size(), 2u);
    indices.insert(row["trial"].get<std::int64_t>());
    EXPECT_TRUE(row["artifacts"].empty()) << row;  // this landscape writes no file
  }
  EXPECT_EQ(indices.size(), 200u);
  // A strategy id is the trial's feature grid cell (search/strategies.h at the task's threshold
  // 0.02: 50 cells per feature over [0, 1]); the basins landscape has several.
  EXPECT_GE(strategies.size(), 2u);
  for (const auto& row : rows) {
    const auto& f = row["features"];
    const std::int64_t cell0 = std::min<std::int64_t>(49, static_cast<std::int64_t>(std::floor(f["f0"].get<double>() / 0.02)));
    const std::int64_t cell1 = std::min<std::int64_t>(49, static_cast<std::int64_t>(std::floor(f["f1"].get<double>() / 0.02)));
    EXPECT_EQ(row["strategy"], cell0 * 50 + cell1) << row;
  }
  // What users read: 1..n per stage, numbered in the order the strategies were first found (done
  // trials by finishing time, the lower index first on a tie), one label per cell.
  std::vector<Json> by_finish(rows.begin(), rows.end());
  std::stable_sort(by_finish.begin(), by_finish.end(), [](const Json& a, const Json& b) {
    return a["finished_at"] != b["finished_at"] ? a["finished_at"].get<double>() < b["finished_at"].get<double>()
                                                : a["trial"].get<std::int64_t>() < b["trial"].get<std::int64_t>();
  });
  std::map<std::int64_t, std::int64_t> expected;
  for (const auto& row : by_finish)
    expected.emplace(row["strategy"].get<std::int64_t>(), static_cast<std::int64_t>(expected.size()) + 1);
  for (const auto& row : rows) EXPECT_EQ(row["strategy_label"], expected.at(row["strategy"].get<std::int64_t>())) << row;

  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  const auto trials = store->campaign_trials(std::stoll(id));
  ASSERT_EQ(trials.size(), 200u);
  EXPECT_EQ(store->metrics(trials[17].id).size(), 5u);  // the smoke preset's 5 metric points
  EXPECT_EQ(store->campaign(std::stoll(id))->state, "done");

  const auto csv = run_podium({"export", id, "--format", "csv"}, dir.path());
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 201);  // header + 200 rows
  const auto status = run_podium({"status", id, "--json"}, dir.path());
  EXPECT_EQ(Json::parse(status.out)["done"], 200);
}

// The set of (trial index, parameters, objectives, features) of a finished campaign.
std::set<std::string> results(const TempDir& dir, const std::string& id) {
  std::set<std::string> out;
  for (const auto& row : export_json(dir, id))
    out.insert(Json{row["trial"], row["params"], row["objectives"], row["features"], row["state"]}.dump());
  return out;
}

bool some_trial_running(const TempDir& dir, const std::string& id) {
  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  for (const auto& t : store->campaign_trials(std::stoll(id)))
    if (t.state == "running") return true;
  return false;
}

// The JSON export names each trial's files (a script finds a trial's policy without the database).
TEST(Cli, JsonExportListsEachTrialsArtifacts) {
  TempDir dir;
  const auto id = submit(dir, landscape_spec(2, {{"artifact", true}}));
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  for (const auto& row : export_json(dir, id)) {
    ASSERT_EQ(row["artifacts"].size(), 1u) << row;
    EXPECT_EQ(row["artifacts"][0]["name"], "result");
    const std::string path = row["artifacts"][0]["path"].get<std::string>();
    EXPECT_TRUE(std::filesystem::path(path).is_absolute()) << path;
    EXPECT_EQ(row["artifacts"][0]["size_bytes"].get<std::int64_t>(), static_cast<std::int64_t>(std::filesystem::file_size(path)));
    EXPECT_EQ(row["artifacts"][0]["sha256"].get<std::string>().size(), 64u);
  }
}

TEST(Cli, KillNineAtRandomMomentsLosesAndRepeatsNothing) {
  const Json spec = landscape_spec(400, {{"sleep_s", 0.008}});
  TempDir reference;
  const auto ref_id = submit(reference, spec);
  ASSERT_EQ(run_podium({"run"}, reference.path()).exit_code, 0);

  TempDir dir;
  const auto id = submit(dir, spec);
  base::Rng rng(2024);  // the kill moments; any seed must pass
  int kills = 0;
  for (int round = 0; round < 40 && kills < 6; ++round) {
    const pid_t pid = podium::testing::spawn_podium({"run"}, dir.path());
    // A random moment once a trial runs: a slow start (a sanitizer build, a loaded machine) would
    // otherwise put every kill before the first attempt.
    if (!podium::testing::wait_until(pid, [&] { return some_trial_running(dir, id); })) break;  // finished
    std::this_thread::sleep_for(std::chrono::milliseconds(rng.integer(0, 200)));
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) break;  // finished before the kill
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    ++kills;
  }
  ASSERT_GE(kills, 5) << "the campaign finished before 5 kills; make it longer";
  const auto final_run = run_podium({"run"}, dir.path());
  ASSERT_EQ(final_run.exit_code, 0) << final_run.err;

  EXPECT_EQ(results(dir, id), results(reference, ref_id));
  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  int interrupted = 0;
  for (const auto& t : store->campaign_trials(std::stoll(id))) {
    int done_attempts = 0;
    for (const auto& a : store->attempts(t.id)) {
      done_attempts += a.state == "done";
      interrupted += a.state == "interrupted";
    }
    EXPECT_EQ(done_attempts, 1) << "trial " << t.index;
  }
  EXPECT_GT(interrupted, 0) << "no attempt was running at any kill: the test did not exercise resume";
}

TEST(Cli, PluginFailuresAreRetriedThenFailedWithTheReason) {
  const Json failures = Json::parse(R"([
    {"mode": "throw", "trials": [3], "attempts": 1},
    {"mode": "segfault", "trials": [5]},
    {"mode": "abort", "trials": [7]},
    {"mode": "hang", "trials": [9]},
    {"mode": "nan", "trials": [11]},
    {"mode": "exit", "trials": [13]},
    {"mode": "throw", "trials": [15]}])");
  TempDir dir;
  const auto id = submit(dir, landscape_spec(24, {{"failures", failures}}, 1, 1.0));
  const auto run = run_podium({"run"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;

  std::map<std::int64_t, Json> by_trial;
  for (const auto& row : export_json(dir, id)) by_trial[row["trial"].get<std::int64_t>()] = row;
  ASSERT_EQ(by_trial.size(), 24u);
  EXPECT_EQ(by_trial[3]["state"], "done");
  EXPECT_EQ(by_trial[3]["attempts"], 2);
  const std::map<std::int64_t, std::string> expected = {{5, "signal 11"},
                                                        {7, "signal 6"},
                                                        {9, "timeout"},
                                                        {11, "non-finite feature f0"},
                                                        {13, "exited with code 3"},
                                                        {15, "injected failure (throw)"}};
  for (const auto& [trial, reason] : expected) {
    EXPECT_EQ(by_trial[trial]["state"], "failed") << trial;
    EXPECT_EQ(by_trial[trial]["attempts"], 2) << trial;
    EXPECT_NE(by_trial[trial]["error"].get<std::string>().find(reason), std::string::npos)
        << trial << ": " << by_trial[trial]["error"];
  }
  int done = 0;
  for (const auto& [trial, row] : by_trial) done += row["state"] == "done";
  EXPECT_EQ(done, 24 - 6);
}

// A stage none of whose trials succeeded ends failed with the reason, and so does its campaign;
// the next stage never starts.
TEST(Cli, AStageWhoseTrialsAllFailedEndsTheCampaignFailed) {
  Json spec = landscape_spec(4, {{"failures", Json::parse(R"([{"mode": "throw"}])")}});
  spec["stages"].push_back({{"name", "refine"},
                            {"task", "landscape"},
                            {"search", {{"algorithm", "random"}}},
                            {"budget", {{"trials", 2}}},
                            {"inputs", {{"stage", "explore"}}}});
  TempDir dir;
  const auto id = submit(dir, spec);
  const auto run = run_podium({"run"}, dir.path());
  ASSERT_EQ(run.exit_code, 1) << run.err;  // a campaign it ran failed
  const std::string reason = "all 4 trials failed (last: trial ";
  const auto status = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(status["state"], "failed");
  EXPECT_EQ(status["error"].get<std::string>().rfind("stage \"explore\" failed: " + reason, 0), 0u) << status["error"];
  EXPECT_NE(status["error"].get<std::string>().find("attempt 2 failed: injected failure (throw)"), std::string::npos);
  EXPECT_EQ(status["stages"][0]["state"], "failed");
  EXPECT_EQ(status["stages"][0]["error"].get<std::string>().rfind(reason, 0), 0u);
  EXPECT_EQ(status["stages"][1]["state"], "waiting");
  const auto text = run_podium({"status"}, dir.path());
  EXPECT_NE(text.out.find("error: stage \"explore\" failed: " + reason), std::string::npos) << text.out;
  auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  std::set<std::string> kinds;
  for (const auto& e : store->events(std::stoll(id))) kinds.insert(e["kind"]);
  EXPECT_TRUE(kinds.count("stage_failed") && kinds.count("campaign_failed"));
  EXPECT_FALSE(kinds.count("campaign_done"));
}

TEST(Cli, BadInputIsOneLineAndLeavesTheDatabaseUnchanged) {
  TempDir dir;
  submit(dir, landscape_spec(3));
  const auto db = dir / "podium.db";
  // Settle the WAL so the main file holds everything before comparing bytes.
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  const std::string before = file_bytes(db);

  auto expect_error = [&](const std::string& spec_text, int code, const std::string& fragment) {
    write_file(dir / "bad.json", spec_text);
    const auto r = run_podium({"submit", "bad.json"}, dir.path());
    EXPECT_EQ(r.exit_code, code) << spec_text;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  expect_error("{\"name\": \"x\",\n \"seed\": 1,, }", 2, "bad.json: invalid JSON at line 2 column");
  Json spec = landscape_spec(3);
  spec["stages"][0]["budget"]["trials"] = 0;
  expect_error(spec.dump(), 2, "bad.json: stages[0].budget.trials: 0 is not in [1, 10000000]");
  spec = landscape_spec(3);
  spec["stages"][0]["task"] = "nope";
  expect_error(spec.dump(), 2, "no file libpodium_task_nope.so");
  spec["stages"][0]["task"] = "landscape_wrong_abi";
  expect_error(spec.dump(), 2, "plugin ABI version 999");
  spec = landscape_spec(3);
  spec["stages"][0]["preset"] = "huge";
  expect_error(spec.dump(), 2, "stages[0].preset: \"huge\" is not a preset of task landscape");
  spec = landscape_spec(3, {{"dimm", 4}});
  expect_error(spec.dump(), 2, "bad.json: stages[0].config.dimm: unknown key (known: artifact, dim, ");
  spec = landscape_spec(3);
  spec["stages"][0]["search"]["algorithm"] = "gradient-descent";
  expect_error(spec.dump(), 2, "unknown algorithm \"gradient-descent\"");
  EXPECT_EQ(file_bytes(db), before);

  const auto unwritable = run_podium({"submit", "spec.json", "--db", "/nonexistent-folder/p.db"}, dir.path());
  EXPECT_EQ(unwritable.exit_code, 1);
  EXPECT_NE(unwritable.err.find("/nonexistent-folder/p.db: cannot open database"), std::string::npos) << unwritable.err;

  // A database written by a newer podium is refused by every command and left as it is.
  { auto store = store::Store::open(dir / "newer.db", store::Store::Access::read_write); }
  const auto bump = run_podium({"status", "--db", "newer.db"}, dir.path());
  ASSERT_EQ(bump.exit_code, 0);
  std::system(("sqlite3 " + (dir / "newer.db").string() + " 'UPDATE schema_version SET version = 42'").c_str());
  const std::string newer_before = file_bytes(dir / "newer.db");
  for (const auto& command : {"run", "status"}) {
    const auto r = run_podium({command, "--db", "newer.db"}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_NE(r.err.find("schema version 42 is newer than this podium supports"), std::string::npos) << r.err;
  }
  EXPECT_EQ(file_bytes(dir / "newer.db"), newer_before);

  const auto usage = run_podium({"run", "--workers", "many"}, dir.path());
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_EQ(run_podium({"frobnicate"}, dir.path()).exit_code, 2);
}

// A spec rejected at submit leaves no database where there was none.
TEST(Cli, ARejectedSpecCreatesNoDatabase) {
  TempDir dir;
  Json spec = landscape_spec(3);
  spec["stages"][0]["preset"] = "nope";
  write_file(dir / "bad.json", spec.dump());
  const auto r = run_podium({"submit", "bad.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("stages[0].preset: \"nope\" is not a preset of task landscape"), std::string::npos) << r.err;
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) files.push_back(entry.path().filename());
  EXPECT_EQ(files, std::vector<std::string>{"bad.json"});
}

// The line `podium submit` prints for a spec: its exit code and its stderr, which must be one line.
podium::testing::CommandResult submit_text(const TempDir& dir, const std::string& text) {
  write_file(dir / "bad.json", text);
  auto r = run_podium({"submit", "bad.json"}, dir.path());
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err.substr(0, 2000);
  return r;
}

// Numbers outside their documented range are refused at submit (exit 2,
// naming the JSON path or option) instead of overflowing, being cut to 32 bits or exhausting memory.
TEST(Cli, NumbersOutOfRangeAreRefusedNamingThePathOrOption) {
  TempDir dir;
  Json spec = landscape_spec(3);
  spec["trial_timeout_s"] = 1e10;
  auto r = submit_text(dir, spec.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: bad.json: trial_timeout_s: 10000000000.0 is not in (0, 31536000]\n");
  spec = landscape_spec(3);
  spec["retries"] = 4294967296;
  r = submit_text(dir, spec.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: bad.json: retries: 4294967296 is not in [0, 100]\n");
  r = submit_text(dir, R"({"name": "x", "seed": 1, "workers": 1e400, "stages": []})");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: bad.json: invalid JSON: number overflow parsing '1e400'\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "podium.db"));

  submit(dir, landscape_spec(3));
  for (const std::string workers : {"2000000000", "1025", "0"}) {
    const auto run = run_podium({"run", "--workers", workers}, dir.path());
    EXPECT_EQ(run.exit_code, 2) << workers;
    EXPECT_EQ(run.err, "podium: --workers: " + workers + " is not in [1, 1024]\n");
  }
}

// A 60,000-deep array crashed submit (signal 11, no output); error lines are
// bounded and control characters in them escaped.
TEST(Cli, DeepNestingAndHugeKeysGiveOneBoundedLine) {
  TempDir dir;
  auto r = submit_text(dir, std::string(60000, '[') + std::string(60000, ']'));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: bad.json: invalid JSON at line 1 column 101: nested deeper than 100 levels\n");

  Json spec = landscape_spec(3);
  spec[std::string(100000, 'k') + "\n\x1b[2J"] = 1;
  r = submit_text(dir, spec.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("podium: bad.json: kkkk", 0), 0u) << r.err.substr(0, 100);
  EXPECT_LE(r.err.size(), 1100u);
  EXPECT_NE(r.err.find("bytes in all)"), std::string::npos) << r.err.substr(900);
  spec = landscape_spec(3);
  spec["bad\nkey\x1b[2J"] = 1;
  r = submit_text(dir, spec.dump());
  EXPECT_EQ(r.err.rfind("podium: bad.json: bad\\x0Akey\\x1B[2J: unknown key", 0), 0u) << r.err;
}

// A campaign name with a control character (a NUL, a terminal escape) is
// refused at submit with its JSON path, so status never prints one raw.
TEST(Cli, NamesWithControlCharactersAreRefusedAtSubmit) {
  TempDir dir;
  Json spec = landscape_spec(3);
  spec["name"] = std::string("a\0b", 3);
  auto r = submit_text(dir, spec.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: bad.json: name: \"a\\u0000b\" has a control character (names are printed and typed)\n");
  spec = landscape_spec(3);
  spec["stages"][0]["name"] = "\x1b]0;owned\x07";
  r = submit_text(dir, spec.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.json: stages[0].name: \"\\u001b]0;owned\\u0007\" has a control character"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "podium.db"));
}

// What a new user tripped over: `run` with nothing to run, pause/resume/cancel and
// `--version` said nothing or were unknown.
TEST(Cli, CommandsSayWhatTheyDid) {
  TempDir dir;
  auto r = run_podium({"run"}, dir.path());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "nothing to run: no database podium.db (podium submit creates it)\n");
  r = run_podium({"pause", "1"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: podium.db: no such database (podium submit creates it)\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "podium.db"));

  const auto id = submit(dir, landscape_spec(3));
  r = run_podium({"pause", id}, dir.path());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, "campaign " + id + " (test) paused: no new trials start, running ones finish\n");
  r = run_podium({"run"}, dir.path());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err,
            "nothing to run: no queued or running campaign in podium.db (podium status lists them; podium "
            "resume continues a paused one)\n");
  r = run_podium({"resume", "test"}, dir.path());
  EXPECT_EQ(r.out, "campaign " + id + " (test) queued again: podium run continues it\n");
  r = run_podium({"cancel", id}, dir.path());
  EXPECT_EQ(r.out, "campaign " + id + " (test) cancelled: running trials are stopped, no new ones start\n");

  const auto version = run_podium({"version"}, dir.path());
  ASSERT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("podium ", 0), 0u);
  const auto dashed = run_podium({"--version"}, dir.path());
  EXPECT_EQ(dashed.exit_code, 0);
  EXPECT_EQ(dashed.out, version.out);
}

// `podium version` names the OpenBLAS kernels in use and who chose them (docs/user-guide.md
// "Install"): a value the user set stands; one podium set on another machine (a Slurm worker's
// inherited environment) is decided afresh here.
TEST(Cli, VersionNamesTheOpenBlasKernelsAndAUsersChoiceStands) {
  TempDir dir;
  const auto version = run_podium({"version"}, dir.path());
  ASSERT_EQ(version.exit_code, 0);
  ASSERT_NE(version.out.find("\nopenblas: "), std::string::npos) << version.out;
  if (version.out.find("openblas: not found") != std::string::npos) GTEST_SKIP() << "OpenBLAS is not installed";
  using podium::testing::shell;
  const std::string binary = podium::testing::podium_binary().string();
  const auto own = shell("env -u OPENBLAS_CORETYPE -u PODIUM_OPENBLAS_CORETYPE " + binary + " version");
  EXPECT_EQ(own.out.find("as set"), std::string::npos) << own.out;
  const auto set = shell("OPENBLAS_CORETYPE=Prescott " + binary + " version");
  EXPECT_NE(set.out.find("openblas: Prescott kernels (OPENBLAS_CORETYPE as set)"), std::string::npos) << set.out;
  const auto elsewhere =
      shell("OPENBLAS_CORETYPE=Prescott PODIUM_OPENBLAS_CORETYPE=Prescott@another-host " + binary + " version");
  EXPECT_EQ(elsewhere.out, own.out) << "decided here as without it";
}

TEST(Cli, EveryCommandHasHelp) {
  TempDir dir;
  for (const auto& command : {"submit", "run", "status", "trials", "log", "pause", "resume", "cancel", "export", "tasks"}) {
    const auto r = run_podium({command, "--help"}, dir.path());
    EXPECT_EQ(r.exit_code, 0) << command;
    EXPECT_NE(r.out.find("--db"), std::string::npos) << command;
  }
}

// Polls `podium status --json` until pred holds or ~20 s pass.
bool wait_for(const TempDir& dir, const std::string& id, const std::function<bool(const Json&)>& pred) {
  for (int i = 0; i < 400; ++i) {
    const auto r = run_podium({"status", id, "--json"}, dir.path());
    if (r.exit_code == 0 && pred(Json::parse(r.out))) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

TEST(Cli, PauseResumeAndCancel) {
  TempDir dir;
  const auto id = submit(dir, landscape_spec(60, {{"sleep_s", 0.05}}));
  const pid_t scheduler = podium::testing::spawn_podium({"run"}, dir.path());
  ASSERT_TRUE(wait_for(dir, id, [](const Json& s) { return s["done"].get<int>() >= 4; }));
  ASSERT_EQ(run_podium({"pause", id}, dir.path()).exit_code, 0);
  // With nothing left to run, the scheduler finishes the attempts in hand and exits.
  EXPECT_EQ(podium::testing::wait_process(scheduler), 0);
  const auto paused = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(paused["state"], "paused");
  EXPECT_EQ(paused["running"], 0);
  EXPECT_LT(paused["done"].get<int>(), 60);

  ASSERT_EQ(run_podium({"resume", id}, dir.path()).exit_code, 0);
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  const auto done = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(done["state"], "done");
  EXPECT_EQ(done["done"], 60);
  EXPECT_EQ(run_podium({"pause", id}, dir.path()).exit_code, 2);  // nothing to pause

  const auto second = submit(dir, landscape_spec(60, {{"sleep_s", 0.05}}));
  const pid_t again = podium::testing::spawn_podium({"run"}, dir.path());
  ASSERT_TRUE(wait_for(dir, second, [](const Json& s) { return s["done"].get<int>() >= 2; }));
  ASSERT_EQ(run_podium({"cancel", second}, dir.path()).exit_code, 0);
  EXPECT_EQ(podium::testing::wait_process(again), 0);
  const auto cancelled = Json::parse(run_podium({"status", second, "--json"}, dir.path()).out);
  EXPECT_EQ(cancelled["state"], "cancelled");
  EXPECT_EQ(cancelled["running"], 0);
  EXPECT_EQ(cancelled["pending"], 0);
}

TEST(Cli, LogJsonPrintsOneEventPerLine) {
  TempDir dir;
  submit(dir, landscape_spec(10));
  const auto r = run_podium({"run", "--log-json"}, dir.path());
  ASSERT_EQ(r.exit_code, 0);
  std::istringstream lines(r.out);
  std::string line;
  std::map<std::string, int> kinds;
  while (std::getline(lines, line)) kinds[Json::parse(line)["event"]]++;
  EXPECT_EQ(kinds["trial_done"], 10);
  EXPECT_EQ(kinds["campaign_done"], 1);
}

TEST(Cli, LaterStageReceivesAnEarlierStagesResults) {
  Json spec = landscape_spec(6);
  spec["stages"].push_back({{"name", "refine"},
                            {"task", "landscape"},
                            {"search", {{"algorithm", "random"}}},
                            {"budget", {{"trials", 4}}},
                            {"inputs", {{"stage", "explore"}, {"select", "best"}}}});
  TempDir dir;
  const auto id = submit(dir, spec);
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  const auto status = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(status["done"], 10);
  EXPECT_EQ(status["stages"][1]["state"], "done");
}

}  // namespace
}  // namespace podium::orchestrator
