// The pool task through the real `podium` CLI: BDS and random search run over a recorded table (a
// synthetic one: a 2-D take-off whose feature is its first coordinate, succeeding below 0.7), each
// trial's result the nearest recorded row's, failed rows without a strategy.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "finished_campaign.h"
#include "process.h"

// Linked for run_campaign_to_end; the pool task does not join the conformance suite (a trial is a
// lookup: nothing to cancel, interrupt or resume).
namespace podium::testing {
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(TaskConformance);
}  // namespace podium::testing

namespace podium::tasks::pool {
namespace {

using nlohmann::json;

json synthetic_table() {
  json rows = json::array();
  int trial = 0;
  for (int i = 0; i <= 10; ++i)
    for (int k = 0; k <= 10; ++k) {
      const double a = i / 10.0, b = k / 10.0;
      rows.push_back({{"trial", trial++}, {"params", {a, b}}, {"success", a < 0.65}, {"features", {a}}, {"bar_m", 1.0 + b}});
    }
  return {{"params", {{{"name", "a"}, {"low", 0.0}, {"high", 1.0}}, {{"name", "b"}, {"low", 0.0}, {"high", 1.0}}}},
          {"features", {{{"name", "f"}, {"low", 0.0}, {"high", 1.0}}}},
          {"strategy_threshold", 0.25},
          {"source", {{"synthetic", true}}},
          {"rows", rows}};
}

json spec(const std::string& table, const std::string& algorithm) {
  return {{"name", "pool-" + algorithm},
          {"seed", 5},
          {"workers", 1},
          {"stages",
           {{{"name", "replay"},
             {"task", "pool"},
             {"config", {{"table", table}}},
             {"search", {{"algorithm", algorithm}}},
             {"budget", {{"trials", 8}}}}}}};
}

TEST(PoolTask, PodiumRunsASearchOverARecordedTable) {
  podium::testing::TempDir dir;
  const auto table = dir / "table.json";
  std::ofstream(table) << synthetic_table().dump();
  for (const std::string algorithm : {"bds", "random"}) {
    std::filesystem::create_directories(dir / algorithm);
    const auto campaign = podium::testing::run_campaign_to_end(dir / algorithm, spec(table.string(), algorithm));
    const auto& trials = campaign.trials.at("replay");
    ASSERT_EQ(trials.size(), 8u) << algorithm;
    for (const auto& t : trials) {
      // Where the trial ran, in the parameters' order, for the search to model it there
      // (search::Observation::x).
      const json& ran = t.result_info.at("evaluated_params");
      ASSERT_EQ(ran.size(), 2u);
      const json recorded = {{"a", ran[0]}, {"b", ran[1]}};
      // The result is the nearest recorded row's: a grid point within half a step of the proposal.
      EXPECT_LE(std::abs(recorded["a"].get<double>() - t.params["a"].get<double>()), 0.05 + 1e-9) << t.params;
      ASSERT_EQ(t.features.size(), 1u);
      EXPECT_DOUBLE_EQ(t.features[0], recorded["a"].get<double>());
      EXPECT_DOUBLE_EQ(t.objectives[0].get<double>(), 1.0 + recorded["b"].get<double>());
      const bool success = t.result_info.at("success").get<bool>();
      EXPECT_EQ(success, t.features[0] < 0.65);
      EXPECT_EQ(t.strategy.has_value(), success) << "a failed recorded jump has no strategy";
    }
  }
}

// feature_set "orientation": the search sees the table's second feature set (here (1 − b, a),
// recorded by the rows with b ≥ 0.25) and looks up only the rows that recorded it.
TEST(PoolTask, ASearchCanSeeTheTablesSecondFeatureSet) {
  podium::testing::TempDir dir;
  json t = synthetic_table();
  t["orientation"] = {{"info", "/rotation"},
                      {"features", {{{"name", "u"}, {"low", 0.0}, {"high", 1.0}}, {{"name", "v"}, {"low", 0.0}, {"high", 1.0}}}},
                      {"strategy_threshold", 0.2}};
  for (auto& row : t["rows"]) {
    const double a = row["params"][0].get<double>(), b = row["params"][1].get<double>();
    if (b >= 0.25) row["orientation"] = {1.0 - b, a};
  }
  const auto table = dir / "table.json";
  std::ofstream(table) << t.dump();
  json s = spec(table.string(), "random");
  s["stages"][0]["config"]["feature_set"] = "orientation";
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), s);
  const auto& trials = campaign.trials.at("replay");
  ASSERT_EQ(trials.size(), 8u);
  for (const auto& trial : trials) {
    const json& ran = trial.result_info.at("evaluated_params");
    const json recorded = {{"a", ran.at(0)}, {"b", ran.at(1)}};
    EXPECT_GE(recorded["b"].get<double>(), 0.25) << "only rows that recorded the set";
    ASSERT_EQ(trial.features.size(), 2u);
    EXPECT_DOUBLE_EQ(trial.features[0], 1.0 - recorded["b"].get<double>());
    EXPECT_DOUBLE_EQ(trial.features[1], recorded["a"].get<double>());
  }
}

}  // namespace
}  // namespace podium::tasks::pool
