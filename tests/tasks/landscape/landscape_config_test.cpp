// The landscape task's config through the real `podium` binary: a value the task does not accept
// is rejected at submit as one line naming its JSON path and what is allowed, exit 2, the database
// unchanged (a bad value of each kind: out of range, not allowed, wrong type, unknown key);
// `podium tasks` shows the keys the same reader validates.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "campaign_spec.h"
#include "podium/base/config.h"
#include "podium/base/json.h"
#include "podium/plugins/loader.h"
#include "process.h"

namespace podium::tasks::landscape {
namespace {

using base::Json;
using podium::testing::file_bytes;
using podium::testing::run_podium;
using podium::testing::TempDir;
using podium::testing::write_file;

Json spec_with(const Json& config) { return podium::testing::stage_spec({.config = config, .trials = 3}); }

TEST(LandscapeConfigAtSubmit, BadValuesAreOneLineWithTheirPathExit2AndTheDatabaseUnchanged) {
  TempDir dir;
  podium::testing::submit_spec(dir.path(), spec_with(Json::object()));
  const auto db = dir / "podium.db";
  // Settle the WAL so the main file holds everything before comparing bytes.
  ASSERT_EQ(run_podium({"run"}, dir.path()).exit_code, 0);
  const std::string before = file_bytes(db);
  const std::string status_before = run_podium({"status", "--json"}, dir.path()).out;

  const std::vector<std::pair<Json, std::string>> cases = {
      // values a user mistypes
      {{{"dim", 0}}, "stages[0].config.dim: 0 is not in [1, 1000]"},
      {{{"family", "bogus"}}, "stages[0].config.family: \"bogus\" is not one of basins, plateaus, plateaus_rough, voronoi"},
      {{{"noise", "abc"}}, "stages[0].config.noise: \"abc\" is not a number"},
      {{{"failures", {{{"mode", "throw"}, {"trials", "all"}}}}},
       "stages[0].config.failures[0].trials: \"all\" is not an array of integers >= 0"},
      // an unknown enum value, a wrong type, out of range, an unknown key
      {{{"failures", {{{"mode", "throw"}}, {{"mode", "explode"}}}}},
       "stages[0].config.failures[1].mode: \"explode\" is not one of throw, segfault, abort, exit, hang, nan"},
      {{{"family", "plateus"}}, "stages[0].config.family: \"plateus\" is not one of basins, plateaus, plateaus_rough, voronoi"},
      {{{"artifact", "yes"}}, "stages[0].config.artifact: \"yes\" is not a boolean (true or false)"},
      {{{"metric_points", 2.5}}, "stages[0].config.metric_points: 2.5 is not an integer"},
      {{{"regions", 1}}, "stages[0].config.regions: 1 is not in [2, 10000]"},
      {{{"fail_fraction", 0.95}}, "stages[0].config.fail_fraction: 0.95 is not in [0, 0.9]"},
      {{{"sleep_s", -1}}, "stages[0].config.sleep_s: -1 is not in [0, 1000000]"},
      {{{"failures", {{{"mode", "hang"}, {"trials", {0, -2}}}}}}, "stages[0].config.failures[0].trials[1]: -2 is not >= 0"},
      {{{"dimm", 4}},
       "stages[0].config.dimm: unknown key (known: artifact, dim, fail_fraction, failures, family, landscape_seed, "
       "metric_points, noise, regions, sleep_s)"},
  };
  for (const auto& [config, message] : cases) {
    write_file(dir / "bad.json", spec_with(config).dump());
    const auto r = run_podium({"submit", "bad.json"}, dir.path());
    EXPECT_EQ(r.exit_code, 2) << config;
    EXPECT_EQ(r.err, "podium: bad.json: " + message + "\n") << config;
    EXPECT_EQ(r.out, "") << config;
  }
  EXPECT_EQ(file_bytes(db), before);
  EXPECT_EQ(run_podium({"status", "--json"}, dir.path()).out, status_before);
}

// A bad value in a later stage is named with that stage's index.
TEST(LandscapeConfigAtSubmit, LaterStagesAreNamedByTheirIndex) {
  TempDir dir;
  Json spec = spec_with(Json::object());
  Json second = spec["stages"][0];
  second["name"] = "second";
  second["config"] = {{"failures", {{{"mode", "throw"}, {"attempts", -1}}}}};
  spec["stages"].push_back(second);
  write_file(dir / "bad.json", spec.dump());
  const auto r = run_podium({"submit", "bad.json"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "podium: bad.json: stages[1].config.failures[0].attempts: -1 is not in [0, 2147483647]\n");
}

TEST(PodiumTasks, JsonDescribesTheConfigTheTaskValidates) {
  TempDir dir;
  const auto r = run_podium({"tasks", "landscape", "--json"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json task = Json::parse(r.out);
  EXPECT_EQ(task["name"], "landscape");
  EXPECT_NE(task["file"].get<std::string>().find("libpodium_task_landscape.so"), std::string::npos);
  EXPECT_EQ(task["params"].size(), 3u);
  EXPECT_EQ(task["features"].size(), 2u);
  EXPECT_EQ(task["metrics"][0]["name"], "trace");
  EXPECT_TRUE(task["presets"].contains("smoke"));

  const Json& keys = task["config"];
  auto key = [&](const std::string& name) {
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const Json& k) { return k["key"] == name; });
    return it == keys.end() ? Json() : *it;
  };
  EXPECT_EQ(key("family")["default"], "basins");
  EXPECT_EQ(key("family")["choices"], Json::parse(R"(["basins", "plateaus", "plateaus_rough", "voronoi"])"));
  EXPECT_EQ(key("dim")["min"], 1);
  EXPECT_EQ(key("noise")["type"], "number");
  const Json failure_keys = key("failures")["items"]["keys"];
  ASSERT_EQ(failure_keys.size(), 3u) << failure_keys;
  EXPECT_EQ(failure_keys[0]["key"], "mode");
  EXPECT_TRUE(failure_keys[0]["required"].get<bool>());
  // The defaults a submit starts from are the described ones, and they are the task's own.
  EXPECT_EQ(task["config_defaults"], base::ConfigReader::defaults(keys));
  EXPECT_EQ(task["config"], plugins::load_task("landscape")->describe(Json::object())["config"]);
}

TEST(PodiumTasks, TextListsEveryInstalledTaskAndItsConfigKeys) {
  TempDir dir;
  const auto r = run_podium({"tasks"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("landscape  ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  params (default config): x0 [0, 1], x1 [0, 1], x2 [0, 1]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  metrics: trace (a synthetic learning curve ending at the objective)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("    smoke  {\"dim\":3,\"metric_points\":5}"), std::string::npos) << r.out;
  for (const std::string line :
       {"    family                 string             \"basins\"     one of basins, plateaus, plateaus_rough, voronoi",
        "    dim                    integer            3            in [1, 1000]",
        "    failures[].mode        string             required     one of throw, segfault, abort, exit, hang, nan"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  // Test plugins stay out of the plain listing; with --all, a plugin that cannot be loaded is
  // listed with the reason instead of ending the listing.
  EXPECT_EQ(r.out.find("landscape_wrong_abi"), std::string::npos) << r.out;
  const auto all = run_podium({"tasks", "--all"}, dir.path());
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_NE(all.out.find("landscape_wrong_abi  ("), std::string::npos) << all.out;
  EXPECT_NE(all.out.find("cannot be described: "), std::string::npos) << all.out;
}

// `--config` describes a task at a config other than its default: its params follow `dim`; a value
// the task rejects is one line naming --config's JSON path.
TEST(PodiumTasks, ConfigDescribesTheTaskAtThatConfig) {
  TempDir dir;
  const auto r = run_podium({"tasks", "landscape", "--json", "--config", "{\"dim\": 2}"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json task = Json::parse(r.out);
  EXPECT_EQ(task["params"].size(), 2u);
  EXPECT_EQ(task["described_with"], Json({{"dim", 2}}));
  const auto text = run_podium({"tasks", "landscape", "--config", "{\"dim\": 2}"}, dir.path());
  EXPECT_NE(text.out.find("  params (config {\"dim\":2}): x0 [0, 1], x1 [0, 1]\n"), std::string::npos) << text.out;
  for (const auto& [args, message] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"tasks", "landscape", "--config", "{\"dim\": 0}"}, "--config.dim: 0 is not"},
           {{"tasks", "landscape", "--config", "[1]"}, "--config: [1] is not a JSON object"},
           {{"tasks", "--config", "{\"dim\": 2}"}, "--config describes one task"}}) {
    const auto bad = run_podium(args, dir.path());
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  }
}

TEST(PodiumTasks, AnUnknownTaskIsOneLineAndExit2) {
  TempDir dir;
  const auto r = run_podium({"tasks", "no_such_task"}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no file libpodium_task_no_such_task.so"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
}  // namespace podium::tasks::landscape
