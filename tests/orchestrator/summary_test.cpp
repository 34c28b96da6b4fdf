// What a researcher reads: objectives and features by the task's names and in its order
// (`trials`, `export`, `status`), `podium summary` of one campaign (best trial, strategies, the
// task's result tables) and of several (their discovery curves), numbers that round-trip.
// Stores built through the store's API where the test needs exact contents, real campaigns of the
// landscape plugin where it needs a search's strategies; real `podium` processes.
#include "podium/store/summary.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <set>
#include <sstream>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;
using store::feature_entries;
using store::format_number;
using store::objective_entries;

// A stage whose task names its objectives and features in an order that is not alphabetical.
store::NewStage named_stage(const std::string& name) {
  store::NewStage s;
  s.name = name;
  s.task = "getup";
  s.algorithm = "random";
  s.description = {
      {"params", Json::array({{{"name", "width"}, {"low", 0}, {"high", 1}}, {{"name", "angle"}, {"low", 0}, {"high", 1}}})},
      {"features", Json::array({{{"name", "zeta"}, {"low", 0}, {"high", 1}, {"unit", "rad"}, {"description", "z"}},
                                {{"name", "alpha"}, {"low", 0}, {"high", 1}}})},
      {"objectives", {"slow_success_rate", "fast_success_rate"}},
      {"objective_info", Json::array({{{"name", "slow_success_rate"}, {"description", "mean slowed success"}},
                                      {{"name", "fast_success_rate"}, {"description", "fast success"}}})}};
  s.budget_trials = 4;
  return s;
}

Json speed_table(double kappa, int rose) {
  return {{"title", "evaluation"},
          {"columns", Json::array({{{"name", "speed"}}, {{"name", "rose"}}, {{"name", "rise time"}, {"unit", "s"}}})},
          {"rows", Json::array({Json::array({"κ " + std::to_string(kappa).substr(0, 4), rose, 1.5}),
                                Json::array({"fast", rose, nullptr})})}};
}

struct Finished {
  std::vector<double> objectives, features;
  std::optional<std::int64_t> strategy;
  Json info = Json::object();
};

// A campaign of named_stage whose trials finish in the given order (trial i: finished[i]); a
// trial without objectives fails.
std::int64_t add_campaign(store::Store& store, const std::string& name, const std::vector<Finished>& finished) {
  const auto id = store.add_campaign(name, Json{{"name", name}}, 1, "", {named_stage("evaluate")});
  const auto stage = store.stages(id)[0].id;
  store.transaction([&] {
    for (std::size_t i = 0; i < finished.size(); ++i) {
      const auto t = store.add_trial(stage, static_cast<std::int64_t>(i), Json{{"angle", 0.25}, {"width", 0.5}}, Json::object(),
                                     Json::object(), i);
      if (finished[i].objectives.empty()) {
        store.set_trial_state(t, "failed", "boom");
        continue;
      }
      store.complete_trial(t, finished[i].objectives, {"zeta", "alpha"}, finished[i].features, finished[i].info, {});
      if (finished[i].strategy) store.set_trial_strategy(t, *finished[i].strategy);
    }
  });
  return id;
}

std::string db_arg(const TempDir& dir) { return (dir / "podium.db").string(); }

TEST(Summary, NamesTheBestTrialStrategiesAndTheTasksTable) {
  TempDir dir;
  std::int64_t id = 0;
  {
    auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_write);
    id = add_campaign(*store, "named",
                      {{{0.5, 0.9}, {0.1, 0.2}, 7, {{"table", speed_table(0.25, 3)}}},
                       {{0.75, 0.8}, {0.9, 0.1}, 3, {{"table", speed_table(0.5, 4)}}},
                       {},
                       {{0.6, 0.7}, {0.15, 0.25}, 7, {{"table", speed_table(0.75, 5)}}}});
  }
  const auto r = run_podium({"summary", "named", "--json", "--db", db_arg(dir)}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json s = Json::parse(r.out);
  EXPECT_EQ(s["campaign"]["id"], id);
  ASSERT_EQ(s["stages"].size(), 1u);
  const Json& st = s["stages"][0];
  EXPECT_EQ(st["trials"]["done"], 3);
  EXPECT_EQ(st["trials"]["failed"], 1);
  // Names in the task's order, with what they mean.
  EXPECT_EQ(st["objectives"][0]["name"], "slow_success_rate");
  EXPECT_EQ(st["objectives"][0]["description"], "mean slowed success");
  EXPECT_EQ(st["features"][0]["name"], "zeta");
  EXPECT_EQ(st["features"][0]["unit"], "rad");
  EXPECT_EQ(st["features"][1]["name"], "alpha");
  // The best trial by the primary objective, its values named.
  EXPECT_EQ(st["best"]["trial"], "evaluate/1");
  EXPECT_EQ(st["best"]["objectives"][0]["name"], "slow_success_rate");
  EXPECT_EQ(st["best"]["objectives"][0]["value"], 0.75);
  EXPECT_EQ(st["best"]["objectives"][1]["value"], 0.8);
  EXPECT_EQ(st["best"]["features"][0]["name"], "zeta");
  EXPECT_EQ(st["best"]["features"][0]["value"], 0.9);
  // Strategies as the store keys them (grid cells 7 and 3), labelled 1..n in the order found, each
  // with its best trial and what it looks like.
  EXPECT_EQ(st["best"]["strategy"], 3);
  EXPECT_EQ(st["best"]["strategy_label"], 2);
  ASSERT_EQ(st["strategies"].size(), 2u);
  EXPECT_EQ(st["strategies"][0]["id"], 7);
  EXPECT_EQ(st["strategies"][0]["label"], 1);
  EXPECT_EQ(st["strategies"][1]["id"], 3);
  EXPECT_EQ(st["strategies"][1]["label"], 2);
  EXPECT_EQ(st["strategies"][0]["trials"], 2);
  EXPECT_EQ(st["strategies"][0]["representative"]["trial"], "evaluate/3");
  EXPECT_EQ(st["strategies"][0]["features"][1]["name"], "alpha");
  EXPECT_EQ(st["strategies"][0]["features"][1]["value"], 0.25);
  EXPECT_EQ(st["strategies"][1]["representative"]["trial"], "evaluate/1");
  // The task's table: every done trial's rows, led by the trial's name, under the named columns.
  ASSERT_EQ(st["tables"].size(), 1u);
  const Json& table = st["tables"][0];
  EXPECT_EQ(table["title"], "evaluation");
  ASSERT_EQ(table["columns"].size(), 4u);
  EXPECT_EQ(table["columns"][0]["name"], "trial");
  EXPECT_EQ(table["columns"][3]["name"], "rise time");
  EXPECT_EQ(table["columns"][3]["unit"], "s");
  ASSERT_EQ(table["rows"].size(), 6u);
  EXPECT_EQ(table["rows"][2], Json::array({"evaluate/1", "κ 0.50", 4, 1.5}));
  EXPECT_EQ(table["rows"][5], Json::array({"evaluate/3", "fast", 5, nullptr}));

  // The text names the same things.
  const auto text = run_podium({"summary", std::to_string(id), "--db", db_arg(dir)}, dir.path());
  ASSERT_EQ(text.exit_code, 0) << text.err;
  for (const char* part :
       {"best: evaluate/1: slow_success_rate 0.75, fast_success_rate 0.8; zeta (rad) 0.9, alpha 0.1; strategy 2", "strategies: 2",
        "rise time (s)", "evaluate/3  fast"})
    EXPECT_NE(text.out.find(part), std::string::npos) << part << " in\n" << text.out;
}

// Keys and columns in the task's order (zeta before alpha, width before angle), not alphabetical;
// numbers at the shortest precision that round-trips.
TEST(Summary, ExportNamesColumnsInTheTasksOrderAtRoundTripPrecision) {
  TempDir dir;
  {
    auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_write);
    add_campaign(*store, "order", {{{0.6, 0.1 + 0.2}, {0.3, 1.0 / 3.0}, 0}});
  }
  const auto csv = run_podium({"export", "order", "--format", "csv", "--db", db_arg(dir)}, dir.path());
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  std::istringstream lines(csv.out);
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  EXPECT_EQ(header,
            "campaign,stage,trial,state,attempts,seed,param.width,param.angle,objective.slow_success_rate,"
            "objective.fast_success_rate,feature.zeta,feature.alpha,strategy,strategy_label,error");
  EXPECT_EQ(row, "1,evaluate,0,done,0,0,0.5,0.25,0.6,0.30000000000000004,0.3,0.3333333333333333,0,1,");

  const auto json = run_podium({"export", "order", "--format", "json", "--db", db_arg(dir)}, dir.path());
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto at = [&](const std::string& key) { return json.out.find("\"" + key + "\""); };
  EXPECT_LT(at("zeta"), at("alpha"));
  EXPECT_LT(at("width"), at("angle"));
  EXPECT_LT(at("slow_success_rate"), at("fast_success_rate"));
  const Json rows = Json::parse(json.out);
  EXPECT_EQ(rows[0]["objectives"]["slow_success_rate"], 0.6);
  EXPECT_EQ(rows[0]["features"]["alpha"], 1.0 / 3.0);
  const auto trials = run_podium({"trials", "order", "--json", "--db", db_arg(dir)}, dir.path());
  EXPECT_EQ(trials.out, json.out);

  // The trials table and status name them too.
  const auto table = run_podium({"trials", "order", "--db", db_arg(dir)}, dir.path());
  EXPECT_EQ(table.out.rfind(
                "trial       state  attempts  slow_success_rate  fast_success_rate  strategy  id  zeta(rad)  alpha  error", 0),
            0u)
      << table.out;
  const auto status = run_podium({"status", "order", "--db", db_arg(dir)}, dir.path());
  EXPECT_NE(status.out.find("objectives: slow_success_rate, fast_success_rate; features: zeta(rad), alpha"), std::string::npos)
      << status.out;
}

TEST(Summary, FormatNumberIsTheShortestTextThatRoundTrips) {
  EXPECT_EQ(format_number(0.6), "0.6");
  EXPECT_EQ(format_number(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(format_number(3.0), "3");
  EXPECT_EQ(format_number(-1e-300), "-1e-300");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  for (int i = 0; i < 1000; ++i) {
    const double x = u(rng);
    const std::string text = format_number(x);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), x) << text;
    char longer[40];
    std::snprintf(longer, sizeof longer, "%.17g", x);
    EXPECT_LE(text.size(), std::string(longer).size());
  }
}

// A store written before objectives had descriptions (names alone) reads the same way.
// What a search concluded, as its saved state's "result" says (CMA-ES: its mean and step sizes in
// parameter units): in the summary's JSON and text; a search whose state has none shows nothing.
TEST(Summary, ShowsTheSearchResultItsSavedStateHolds) {
  TempDir dir;
  const Json result = {{"algorithm", "cmaes"},
                       {"mean", {{"width", 0.25}, {"angle", 0.5}}},
                       {"covariance", Json::array({Json::array({0.01, 0.0}), Json::array({0.0, 0.04})})},
                       {"step_sizes", {{"width", 0.1}, {"angle", 0.2}}},
                       {"generations", 7},
                       {"stopped", true}};
  {
    auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_write);
    add_campaign(*store, "searched", {{{0.5, 0.9}, {0.1, 0.2}, 7}});
    add_campaign(*store, "plain", {{{0.5, 0.9}, {0.1, 0.2}, 7}});
    store->save_search_state(store->stages(1)[0].id, {{"rng", "x"}, {"result", result}}, 1.0, 1);
  }
  const auto r = run_podium({"summary", "searched", "--json", "--db", db_arg(dir)}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["stages"][0]["search_result"], result);
  const auto text = run_podium({"summary", "searched", "--db", db_arg(dir)}, dir.path());
  EXPECT_NE(text.out.find("search result: mean angle 0.5 width 0.25; step sizes angle 0.2 width 0.1; 7 generations, "
                          "converged (step-size stop)"),
            std::string::npos)
      << text.out;
  const auto plain = run_podium({"summary", "plain", "--json", "--db", db_arg(dir)}, dir.path());
  EXPECT_TRUE(Json::parse(plain.out)["stages"][0]["search_result"].is_null());
  EXPECT_EQ(run_podium({"summary", "plain", "--db", db_arg(dir)}, dir.path()).out.find("search result"), std::string::npos);
}

TEST(Summary, ReadsAStageWithoutObjectiveInfo) {
  Json old = {{"objectives", {"objective"}}, {"features", Json::array({{{"name", "f0"}, {"low", 0}, {"high", 1}}})}};
  EXPECT_EQ(objective_entries(old), Json::parse(R"([{"name": "objective"}])"));
  EXPECT_EQ(feature_entries(old), Json::parse(R"([{"name": "f0"}])"));
  EXPECT_EQ(objective_entries(Json::object()), Json::array());
}

// A database an older Podium wrote (the store's saved schema-1 file, migrated): its stages have
// objective names but no objective_info; summary and export still name everything.
TEST(Summary, ReadsADatabaseAnOlderPodiumWrote) {
  TempDir dir;
  std::filesystem::copy_file(std::string(PODIUM_SOURCE_DIR) + "/tests/store/testdata/schema_v1.db", dir / "podium.db");
  store::Store::open(dir / "podium.db", store::Store::Access::read_write);  // migrates
  const auto r = run_podium({"summary", "1", "--json"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json stage = Json::parse(r.out)["stages"][0];
  EXPECT_EQ(stage["objectives"], Json::parse(R"([{"name": "objective"}])"));
  EXPECT_EQ(stage["best"]["objectives"][0]["name"], "objective");
  EXPECT_FALSE(stage["strategies"].empty());
  const auto csv = run_podium({"export", "1", "--format", "csv"}, dir.path());
  EXPECT_EQ(
      csv.out.rfind(
          "campaign,stage,trial,state,attempts,seed,param.x0,param.x1,param.x2,objective.objective,feature.f0,feature.f1,", 0),
      0u)
      << csv.out;
}

// A task names its objectives per stage from the stage's config: the demo's get-up Evaluate stage
// ranks by the mean slowed success, its training stage by the success rate; the jumps' (high and
// obstacle) by their jumps' success; the curve edits by the edited curve's success, then r_task.
// Submitted (each stage described by its plugin), not run.
TEST(Summary, ObjectivesAreNamedPerStageByTheTasksDescription) {
  TempDir dir;
  const auto submit = run_podium({"submit", std::string(PODIUM_SOURCE_DIR) + "/campaigns/getup_demo.json"}, dir.path());
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const auto status = run_podium({"status", "getup-demo", "--json"}, dir.path());
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const Json stages = Json::parse(status.out)["stages"];
  ASSERT_EQ(stages.size(), 6u);
  const auto names = [](const Json& entries) {
    std::vector<std::string> out;
    for (const auto& e : entries) out.push_back(e["name"]);
    return out;
  };
  for (const int evaluate : {0, 1}) {  // the seed body's π_weak alone, then the earlier body's pair
    EXPECT_EQ(names(stages[evaluate]["objectives"]), (std::vector<std::string>{"slow_success_rate", "fast_success_rate"}));
    EXPECT_NE(stages[evaluate]["objectives"][0]["description"].get<std::string>().find("mean slowed success"), std::string::npos);
    EXPECT_EQ(names(stages[evaluate]["features"]),
              (std::vector<std::string>{"chest_up_at_half_height", "side_lean", "hand_support", "knee_support"}));
  }
  for (const int jumps : {2, 3}) {  // the high jumps, then the obstacle jumps
    EXPECT_EQ(names(stages[jumps]["objectives"]), std::vector<std::string>{"success_rate"});
    EXPECT_EQ(stages[jumps]["features"][0]["unit"], "rad");
  }
  EXPECT_EQ(names(stages[4]["objectives"]), (std::vector<std::string>{"success_rate", "weakness"}));
  EXPECT_EQ(names(stages[5]["objectives"]), (std::vector<std::string>{"success_rate", "mean_r_task"}));
  for (const auto& stage : stages)
    for (const auto& entry : stage["objectives"]) EXPECT_TRUE(entry.contains("description")) << stage["name"] << entry;
}

// Two real landscape campaigns (BDS and random) side by side: one discovery curve each, ending at
// the strategies its trials have, each point no higher than the samples behind it.
TEST(Summary, SeveralCampaignsGiveEachItsDiscoveryCurve) {
  TempDir dir;
  std::vector<std::string> ids;
  for (const char* algorithm : {"random", "bds"})
    ids.push_back(podium::testing::submit_spec(
        dir.path(),
        podium::testing::stage_spec(
            {.name = std::string("curve-") + algorithm, .seed = 3, .workers = 1, .algorithm = algorithm, .trials = 8})));
  const auto run = run_podium({"run", "--workers", "1"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto r = run_podium({"summary", ids[0], ids[1], "--json"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json s = Json::parse(r.out);
  ASSERT_EQ(s["campaigns"].size(), 2u);
  ASSERT_EQ(s["stages"].size(), 1u);
  const Json& curves = s["stages"][0]["curves"];
  ASSERT_EQ(curves.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c) {
    SCOPED_TRACE(ids[c]);
    EXPECT_EQ(curves[c]["campaign"], std::stoll(ids[c]));
    const auto rows = Json::parse(run_podium({"export", ids[c], "--format", "json"}, dir.path()).out);
    std::set<std::int64_t> strategies;
    for (const auto& row : rows)
      if (!row["strategy"].is_null()) strategies.insert(row["strategy"].get<std::int64_t>());
    const Json& curve = curves[c]["discovery"];
    ASSERT_FALSE(curve.empty());
    EXPECT_EQ(curve.back()[0], rows.size());
    EXPECT_EQ(curve.back()[1], strategies.size());
    for (std::size_t i = 0; i < curve.size(); ++i) {
      EXPECT_LE(curve[i][1].get<int>(), curve[i][0].get<int>());
      if (i == 0) continue;
      EXPECT_GT(curve[i][0].get<int>(), curve[i - 1][0].get<int>());
      EXPECT_GE(curve[i][1].get<int>(), curve[i - 1][1].get<int>());
    }
  }
  const auto text = run_podium({"summary", ids[0], ids[1]}, dir.path());
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("[curve-random]"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("|  [curve-bds]"), std::string::npos) << text.out;
}

}  // namespace
}  // namespace podium::orchestrator
