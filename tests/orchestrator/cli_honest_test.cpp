// Predictable paths and honest exits: spec file paths relative to the spec, checked at submit and
// stored absolute; `run` exits 1 when a campaign it ran failed; unknown keys named with every
// known key; near names for a missing campaign or task; test plugins out of `podium tasks`;
// `status` after a killed scheduler; `podium tool` (a task's command-line tool) with the probe's.
// Real `podium` processes and the probe task.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <set>
#include <thread>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

namespace fs = std::filesystem;
using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;
using podium::testing::write_file;

Json probe_spec(const Json& config, int trials = 2, int retries = 0) {
  return podium::testing::stage_spec({.retries = retries, .task = "probe", .config = config, .trials = trials});
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(CliHonest, RunExitsOneWhenACampaignItRanFailed) {
  TempDir dir;
  // Every attempt throws at its first step and there are no retries: no trial succeeds.
  podium::testing::submit_spec(dir.path(), probe_spec({{"fail_step", 0}, {"fail_attempts", 100}}));
  const auto run = run_podium({"run"}, dir.path());
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_TRUE(contains(run.err, "campaign 1 (test) failed")) << run.err;
  // A later run with nothing left to do has nothing failed to report.
  EXPECT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
}

TEST(CliHonest, SpecRelativeFilePathsRunFromAnyFolder) {
  TempDir dir;
  fs::create_directories(dir / "data");
  write_file(dir / "data" / "x.txt", "x\n");
  write_file(dir / "data" / "policy.pt", "p\n");
  fs::create_directories(dir / "specs");
  fs::create_directories(dir / "elsewhere");
  write_file(
      dir / "specs" / "spec.json",
      probe_spec({{"data_file", "../data/x.txt"}, {"shipped", {{{"policy", "../data/policy.pt"}}}}, {"data_path", "../data"}})
          .dump());
  // Submitted and run from a folder that is neither the spec's nor the files'.
  const std::string db = (dir / "podium.db").string();
  const auto submit = run_podium({"submit", "../specs/spec.json", "--db", db}, dir / "elsewhere");
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const auto run = run_podium({"run", "--db", db}, fs::path("/"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json rows = Json::parse(run_podium({"export", "1", "--format", "json", "--db", db}, dir.path()).out);
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    EXPECT_EQ(row["state"], "done");
    const Json& info = row["result"];
    EXPECT_EQ(info["data_file"]["path"], (dir / "data" / "x.txt").string()) << info;
    EXPECT_TRUE(info["data_file"]["exists"].get<bool>());
    EXPECT_EQ(info["shipped"][0]["path"], (dir / "data" / "policy.pt").string()) << info;
    EXPECT_TRUE(info["shipped"][0]["exists"].get<bool>());
    EXPECT_EQ(info["data_path"]["path"], (dir / "data").string()) << info;  // a folder ("format": "path")
  }
}

TEST(CliHonest, AMissingFileFailsAtSubmitNamingThePathAsWrittenAndAsResolved) {
  TempDir dir;
  fs::create_directories(dir / "specs");
  write_file(dir / "specs" / "spec.json", probe_spec({{"shipped", {{{"policy", "policies/nope.pt"}}}}}).dump());
  const auto r = run_podium({"submit", "specs/spec.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  const std::string resolved = (dir / "specs" / "policies" / "nope.pt").string();
  EXPECT_TRUE(contains(r.err, "stages[0].config.shipped[0].policy: \"policies/nope.pt\" is not a file (looked for " + resolved +
                                  "; a relative path is relative to the spec's folder)"))
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "podium.db"));
  // A folder where a file is declared is refused; where a file or folder is ("format": "path"), a
  // missing one is refused the same way.
  fs::create_directories(dir / "specs" / "folder");
  write_file(dir / "specs" / "spec.json", probe_spec({{"data_file", "folder"}}).dump());
  EXPECT_TRUE(contains(run_podium({"submit", "specs/spec.json"}, dir.path()).err, "data_file: \"folder\" is not a file (looked"));
  write_file(dir / "specs" / "spec.json", probe_spec({{"data_path", "nowhere"}}).dump());
  const auto missing = run_podium({"submit", "specs/spec.json"}, dir.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(contains(missing.err, "stages[0].config.data_path: \"nowhere\" is not a file or folder (looked for "))
      << missing.err;
  EXPECT_FALSE(fs::exists(dir / "podium.db"));
}

TEST(CliHonest, AMisspeltKeyNamesItselfAndListsEveryKnownKey) {
  TempDir dir;
  Json spec = probe_spec(Json::object());
  spec["stages"][0]["budjet"] = spec["stages"][0]["budget"];
  spec["stages"][0].erase("budget");
  write_file(dir / "stage.json", spec.dump());
  auto r = run_podium({"submit", "stage.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "podium: stage.json: stages[0].budjet: unknown key (known: name, task, preset, config, search, "
            "strategy_threshold, inputs, budget) (did you mean budget?)\n");
  spec = probe_spec(Json::object());
  spec["executer"] = {{"kind", "local"}};
  write_file(dir / "top.json", spec.dump());
  r = run_podium({"submit", "top.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "podium: top.json: executer: unknown key (known: name, seed, description, run_dir, executor, workers, "
            "retries, trial_timeout_s, stages) (did you mean executor?)\n");
}

TEST(CliHonest, AMissingCampaignOrTaskSuggestsTheNearestNames) {
  TempDir dir;
  Json spec = probe_spec(Json::object());
  spec["name"] = "getup-demo";
  podium::testing::submit_spec(dir.path(), spec);
  auto r = run_podium({"status", "getup_demo"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: no campaign \"getup_demo\" in podium.db (did you mean getup-demo?)\n");
  spec["stages"][0]["task"] = "landscap";
  write_file(dir / "typo.json", spec.dump());
  r = run_podium({"submit", "typo.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "typo.json: stages[0].task: plugin \"landscap\": no file")) << r.err;
  EXPECT_TRUE(contains(r.err, "installed tasks: ")) << r.err;
  EXPECT_TRUE(contains(r.err, "(did you mean landscape?)")) << r.err;
  EXPECT_FALSE(contains(r.err, "probe")) << "test plugins are not offered: " << r.err;
}

TEST(CliHonest, TestPluginsAreListedOnlyWithAll) {
  TempDir dir;
  const auto names = [&](const std::vector<std::string>& args) {
    const auto r = run_podium(args, dir.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::set<std::string> out;
    for (const auto& t : Json::parse(r.out)) out.insert(t["name"].get<std::string>());
    return out;
  };
  const auto installed = names({"tasks", "--json"});
  EXPECT_TRUE(installed.count("landscape"));
  for (const char* test_plugin : {"probe", "landscape_wrong_abi", "web_replay_fixture"})
    EXPECT_FALSE(installed.count(test_plugin)) << test_plugin;
  const auto all = names({"tasks", "--json", "--all"});
  EXPECT_TRUE(all.count("probe"));
  EXPECT_TRUE(all.count("landscape_wrong_abi"));
}

// Polls `podium status --json` until pred holds or ~20 s pass.
bool wait_for(const TempDir& dir, const std::function<bool(const Json&)>& pred) {
  for (int i = 0; i < 400; ++i) {
    const auto r = run_podium({"status", "1", "--json"}, dir.path());
    if (r.exit_code == 0 && pred(Json::parse(r.out))) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

TEST(CliHonest, StatusAfterAKilledSchedulerShowsNoTrialRunning) {
  TempDir dir;
  podium::testing::submit_spec(dir.path(), probe_spec({{"steps", 1000}, {"sleep_s", 0.05}}, 4));
  const pid_t scheduler = podium::testing::spawn_podium({"run", "--workers", "2"}, dir.path());
  ASSERT_TRUE(wait_for(dir, [](const Json& s) { return s["running"].get<int>() == 2; }));
  ::kill(scheduler, SIGKILL);
  podium::testing::wait_process(scheduler);
  const Json s = Json::parse(run_podium({"status", "1", "--json"}, dir.path()).out);
  EXPECT_EQ(s["scheduler"], "none");
  EXPECT_EQ(s["running"], 0) << s;
  EXPECT_EQ(s["pending"], 2) << s;  // the two that were running: `podium run` runs them again
  EXPECT_EQ(s["stages"][0]["running"], 0) << s;
  EXPECT_EQ(s["stages"][0]["running_attempts"].size(), 2u);
  const auto table = run_podium({"status"}, dir.path());
  EXPECT_TRUE(contains(table.out, "stopped")) << table.out;
}

// One line on stderr, ending in a newline.
bool one_line(const std::string& text) { return !text.empty() && text.find('\n') == text.size() - 1; }

TEST(CliTool, ListsTheTasksWithToolsAndATasksCommands) {
  TempDir dir;
  // The probe is a test plugin: listed with --all only.
  const auto plain = run_podium({"tool"}, dir.path());
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_FALSE(contains(plain.out, "probe")) << plain.out;
  const auto all = run_podium({"tool", "--all"}, dir.path());
  EXPECT_EQ(all.exit_code, 0) << all.err;
  EXPECT_TRUE(contains(all.out, "probe            echo, reject, fail")) << all.out;
  EXPECT_FALSE(contains(all.out, "landscape ")) << all.out;  // a task without tools is not listed
  for (const std::vector<std::string>& args : {std::vector<std::string>{"tool", "probe"}, {"tool", "probe", "--help"}}) {
    const auto help = run_podium(args, dir.path());
    EXPECT_EQ(help.exit_code, 0) << help.err;
    EXPECT_TRUE(contains(help.out, "usage: podium tool probe COMMAND")) << help.out;
    EXPECT_TRUE(contains(help.out, "  echo [ARGS...]\n      prints its arguments, one a line")) << help.out;
  }
}

TEST(CliTool, RunsACommandWithItsArgumentsAndItsExitCode) {
  TempDir dir;
  const auto echo = run_podium({"tool", "probe", "echo", "a b", "--x=1"}, dir.path());
  EXPECT_EQ(echo.exit_code, 0) << echo.err;
  EXPECT_EQ(echo.out, "a b\n--x=1\n");
  const auto fail = run_podium({"tool", "probe", "fail"}, dir.path());
  EXPECT_EQ(fail.exit_code, 1);
  EXPECT_EQ(fail.err, "probe fail: failed as asked\n");
  // A user error thrown by the plugin: one line, exit 2.
  const auto reject = run_podium({"tool", "probe", "reject"}, dir.path());
  EXPECT_EQ(reject.exit_code, 2);
  EXPECT_TRUE(contains(reject.err, "probe reject: refused as asked")) << reject.err;
  EXPECT_TRUE(one_line(reject.err)) << reject.err;
}

TEST(CliTool, BadInputIsOneLineWithExitTwo) {
  TempDir dir;
  const auto typo = run_podium({"tool", "probe", "ehco"}, dir.path());
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_TRUE(contains(typo.err, "podium tool probe: no command \"ehco\" (did you mean echo?); commands: echo, reject, fail"))
      << typo.err;
  EXPECT_TRUE(one_line(typo.err)) << typo.err;
  const auto none = run_podium({"tool", "landscape", "x"}, dir.path());
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_EQ(none.err, "podium tool: task \"landscape\" has no tools\n");
  const auto missing = run_podium({"tool", "landscap"}, dir.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(contains(missing.err, "plugin \"landscap\"")) << missing.err;
  EXPECT_TRUE(contains(missing.err, "did you mean landscape")) << missing.err;
  EXPECT_TRUE(one_line(missing.err)) << missing.err;
  const auto option = run_podium({"tool", "--bogus"}, dir.path());
  EXPECT_EQ(option.exit_code, 2);
  EXPECT_TRUE(contains(option.err, "podium tool: unknown option \"--bogus\"")) << option.err;
}

}  // namespace
}  // namespace podium::orchestrator
