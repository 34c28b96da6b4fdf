// The pool table (tasks/pool) and its replay (bench/search) on a synthetic table: a 1-D take-off x in [0, 1] whose feature is
// x itself, succeeding below 0.8, recorded on a grid of 101 points.
#include "pool_replay.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "podium/base/error.h"

namespace podium::bench::pool {
namespace {

base::Json synthetic_table() {
  base::Json rows = base::Json::array();
  for (int i = 0; i <= 100; ++i) {
    const double x = i / 100.0;
    rows.push_back({{"trial", i}, {"params", {x}}, {"success", x < 0.795}, {"features", {x}}, {"bar_m", 1.0 - x}});
  }
  rows[50]["finished"] = false;  // one recorded trial failed outright
  rows[50]["features"] = nullptr;
  return {{"params", {{{"name", "x"}, {"low", 0.0}, {"high", 1.0}}}},
          {"features", {{{"name", "f"}, {"low", 0.0}, {"high", 1.0}}}},
          {"strategy_threshold", 0.25},
          {"rows", rows}};
}

TEST(PoolTable, LooksUpTheNearestRecordedTakeOff) {
  const PoolTable t = PoolTable::parse(synthetic_table(), "table.json");
  EXPECT_EQ(t.nearest({0.333}), 33u);
  EXPECT_EQ(t.nearest({-5.0}), 0u);
  EXPECT_FALSE(t.rows[50].finished);
  const auto lookup = outcome(t);
  EXPECT_FALSE(lookup({0.9}).has_value());  // failed to clear
  EXPECT_FALSE(lookup({0.5}).has_value());  // failed outright
  EXPECT_DOUBLE_EQ(lookup({0.2})->at(0), 0.2);
  const PoolTable again = PoolTable::parse(t.to_json(), "round trip");
  EXPECT_EQ(again.rows.size(), t.rows.size());
  EXPECT_EQ(again.rows[50].finished, false);
}

TEST(PoolTable, BadInputNamesTheFileAndPath) {
  base::Json j = synthetic_table();
  j["rows"][3]["params"] = {0.1, 0.2};
  try {
    PoolTable::parse(j, "table.json");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("table.json: rows[3].params: expected 1 numbers"), std::string::npos) << e.what();
  }
  j = synthetic_table();
  j["rows"][4]["success"] = "yes";
  EXPECT_THROW(PoolTable::parse(j, "table.json"), base::UserError);
}

TEST(PoolReplay, RandomMatchesItsExpectationAndCountsStayUnderTheCeiling) {
  const PoolTable t = PoolTable::parse(synthetic_table(), "table.json");
  ReplayOptions o;
  o.reps = 200;
  o.budgets = {5, 10};
  o.expected_draws = 20000;
  o.configs["bds"] = {{"direct_evals", 100}, {"explore_candidates", 64}};
  const ReplayResult r = replay(t, o);
  // Successes span [0, 0.79]: on 4 cells of 0.25 that is cells 0–3; on 2 cells of 0.5, both.
  ASSERT_EQ(r.countings.size(), 2u);  // the first feature set at τ and 2τ; no second set
  EXPECT_EQ(r.countings[0].ceiling, 4);
  EXPECT_EQ(r.countings[1].ceiling, 2);
  EXPECT_EQ(r.countings[0].occupied, 4);
  ASSERT_EQ(r.arms.size(), 3u);
  for (std::size_t b = 0; b < 2; ++b) {
    std::vector<double> random, failures;
    for (const auto& rep : r.arms.at("random").counts[0]) random.push_back(rep[b]);
    for (const auto& rep : r.arms.at("random").failures) failures.push_back(rep[b]);
    const MeanSd m = mean_sd(random), f = mean_sd(failures);
    // Random's replayed mean agrees with the Monte Carlo expectation within 4 standard errors.
    EXPECT_NEAR(m.mean, r.countings[0].random_expected[b], 4.0 * m.sd / std::sqrt(200.0) + 0.02) << o.budgets[b];
    // Each draw fails with probability ≈ 0.215 (x ≥ 0.795, plus the row that failed outright).
    EXPECT_NEAR(f.mean, 0.215 * o.budgets[b], 4.0 * f.sd / std::sqrt(200.0) + 0.02) << o.budgets[b];
    for (const auto& [arm, runs] : r.arms)
      for (const auto& rep : runs.counts[0]) EXPECT_LE(rep[b], r.countings[0].ceiling) << arm;
  }
  // Paired by seed and deterministic: a second replay gives the same runs.
  o.arms = {"random"};
  const ReplayResult again = replay(t, o);
  EXPECT_EQ(again.arms.at("random").counts, r.arms.at("random").counts);
}

// A second feature set (a jump's 3-D bar-frame rotation): here 2-D, (1 − x, 0), recorded by every
// row but those below x = 0.1. It is counted beside the first for the same replays, at its own
// threshold and twice it, with its ceiling and random's expectation, over the rows that recorded
// it; the table keeps it through a round trip.
TEST(PoolReplay, ASecondFeatureSetIsCountedBesideTheFirst) {
  base::Json j = synthetic_table();
  j["orientation"] = {{"info", "/rotation"},
                      {"features", {{{"name", "a"}, {"low", 0.0}, {"high", 1.0}}, {{"name", "b"}, {"low", -1.0}, {"high", 1.0}}}},
                      {"strategy_threshold", 0.1}};
  for (auto& row : j["rows"]) {
    const double x = row["params"][0].get<double>();
    if (x >= 0.095) row["orientation"] = {1.0 - x, 0.0};
  }
  const PoolTable t = PoolTable::parse(j, "table.json");
  EXPECT_TRUE(t.rows[3].orientation.empty());
  EXPECT_EQ(t.rows[30].orientation, std::vector<double>({0.7, 0.0}));
  EXPECT_TRUE(t.rows[50].orientation.empty());  // failed outright: nothing recorded
  const PoolTable again = PoolTable::parse(t.to_json(), "round trip");
  EXPECT_EQ(again.rows[30].orientation, t.rows[30].orientation);
  EXPECT_EQ(again.orientation_threshold, 0.1);

  ReplayOptions o;
  o.reps = 100;
  o.budgets = {5, 10};
  o.arms = {"random"};
  const ReplayResult r = replay(t, o);
  ASSERT_EQ(r.countings.size(), 4u);
  const Counting &fine = r.countings[2], &coarse = r.countings[3];
  EXPECT_TRUE(fine.orientation && coarse.orientation);
  EXPECT_EQ(fine.threshold, 0.1);
  EXPECT_EQ(coarse.threshold, 0.2);
  // Successes that recorded it: x in [0.1, 0.79], so a in [0.21, 0.9]: cells 2–9 of 10 at 0.1
  // (b's 20 cells: one), cells 1–4 of 5 at 0.2.
  EXPECT_EQ(fine.ceiling, 8);
  EXPECT_EQ(fine.occupied, 8);
  EXPECT_EQ(coarse.ceiling, 4);
  const auto& runs = r.arms.at("random");
  ASSERT_EQ(runs.counts[2].size(), 100u);
  for (std::size_t b = 0; b < 2; ++b) {
    std::vector<double> counts;
    for (std::size_t k = 0; k < runs.counts[2].size(); ++k) {
      counts.push_back(runs.counts[2][k][b]);
      EXPECT_LE(runs.counts[2][k][b], fine.ceiling);
      EXPECT_LE(runs.counts[3][k][b], runs.counts[2][k][b]);
    }
    const MeanSd m = mean_sd(counts);
    EXPECT_NEAR(m.mean, fine.random_expected[b], 4.0 * m.sd / std::sqrt(100.0) + 0.02) << o.budgets[b];
  }
  // Searched by it: its rows only (x ≥ 0.095, and row 50 that failed outright), its features and
  // threshold first, the first set second; a replay then counts it first.
  const PoolTable by = t.by_orientation();
  EXPECT_EQ(by.rows.size(), 91u);
  EXPECT_EQ(by.features.size(), 2u);
  EXPECT_EQ(by.strategy_threshold, 0.1);
  EXPECT_EQ(by.orientation_threshold, 0.25);
  EXPECT_EQ(by.rows[20].features, t.rows[30].orientation);
  EXPECT_EQ(by.rows[20].orientation, t.rows[30].features);
  const ReplayResult swapped = replay(by, o);
  ASSERT_EQ(swapped.countings.size(), 4u);
  EXPECT_FALSE(swapped.countings[0].orientation);
  EXPECT_EQ(swapped.countings[0].threshold, 0.1);
  EXPECT_EQ(swapped.countings[0].ceiling, fine.ceiling);
  EXPECT_EQ(swapped.countings[2].threshold, 0.25);
  EXPECT_THROW(PoolTable::parse(synthetic_table(), "table.json").by_orientation(), base::UserError);
  // Without one, nothing is counted.
  const ReplayResult plain = replay(PoolTable::parse(synthetic_table(), "table.json"), o);
  EXPECT_EQ(plain.countings.size(), 2u);
  EXPECT_EQ(plain.arms.at("random").counts.size(), 2u);
}

// BDS's default treatment of failed samples (bds.h "Failed samples") against Algorithm 1 read
// literally, on the same table and seeds: the literal reading explores into the failing end of
// the box (x ≥ 0.795) more often than random does; modelling the success probability fails less.
TEST(PoolReplay, BdsModellingFailuresFailsLessThanTheLiteralReading) {
  const PoolTable t = PoolTable::parse(synthetic_table(), "table.json");
  std::map<std::string, MeanSd> failures;
  for (const std::string mode : {"model", "ignore"}) {
    ReplayOptions o;
    o.arms = {"bds"};
    o.reps = 100;
    o.budgets = {10};
    o.expected_draws = 10;
    o.configs["bds"] = {{"direct_evals", 100}, {"explore_candidates", 64}, {"failures", mode}};
    const ReplayResult r = replay(t, o);
    std::vector<double> v;
    for (const auto& rep : r.arms.at("bds").failures) v.push_back(rep[0]);
    failures[mode] = mean_sd(v);
  }
  const double se = std::hypot(failures["model"].sd, failures["ignore"].sd) / std::sqrt(100.0);
  EXPECT_LT(failures["model"].mean, failures["ignore"].mean - 4.0 * se)
      << "model " << failures["model"].mean << ", ignore " << failures["ignore"].mean;
}

}  // namespace
}  // namespace podium::bench::pool
