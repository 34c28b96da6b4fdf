#include "podium/search/strategies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "podium/base/error.h"

namespace podium::search {
namespace {

std::vector<Feature> features(const std::vector<FeatureMetric>& metrics, double low = -4.0, double high = 4.0) {
  std::vector<Feature> out;
  for (auto m : metrics) out.push_back(Feature{"f" + std::to_string(out.size()), low, high, m, "", false});
  return out;
}

TEST(FeatureDistance, AngularWrapsAroundAndEuclideanDoesNot) {
  const auto f = features({FeatureMetric::angular, FeatureMetric::euclidean});
  const double pi = std::numbers::pi;
  EXPECT_NEAR(feature_distance(f, {-pi + 0.1, 0.0}, {pi - 0.1, 0.0}), 0.2, 1e-12);
  EXPECT_NEAR(feature_distance(f, {0.0, -pi + 0.1}, {0.0, pi - 0.1}), 2 * pi - 0.2, 1e-12);
  EXPECT_NEAR(feature_distance(f, {0.0, 0.0}, {3 * pi, 4.0}), std::hypot(pi, 4.0), 1e-12);  // 3π wraps to π
}

TEST(StrategyGrid, CellsAreAboutTheThresholdWideAndOutOfRangeValuesJoinTheEndCells) {
  // [0, π] at τ = 0.5: round(6.28) = 6 cells of π/6; at 2τ, 3 cells of π/3 (the jump's grids).
  const auto f = features({FeatureMetric::euclidean}, 0.0, std::numbers::pi);
  EXPECT_EQ(strategy_cells_per_feature(f, 0.5), (std::vector<std::int64_t>{6}));
  EXPECT_EQ(strategy_cells_per_feature(f, 1.0), (std::vector<std::int64_t>{3}));
  EXPECT_EQ(strategy_ids(f, {{0.1}, {0.6}, {1.1}, {-3.0}, {9.0}}, 0.5), (std::vector<std::int64_t>{0, 1, 2, 0, 5}));
  // Two features: feature 0 varies slowest.
  const auto g = features({FeatureMetric::euclidean, FeatureMetric::euclidean}, 0.0, 1.0);
  EXPECT_EQ(strategy_id(g, {0.55, 0.15}, 0.25), 2 * 4 + 0);
}

TEST(StrategyGrid, AngularCellsWrapAroundTheTurn) {
  const auto f = features({FeatureMetric::angular}, -std::numbers::pi, std::numbers::pi);
  const double pi = std::numbers::pi;
  EXPECT_EQ(strategy_id(f, {-pi + 0.05}, 0.5), strategy_id(f, {pi + 0.05}, 0.5));
  EXPECT_EQ(strategy_id(f, {3 * pi - 0.01}, 0.5), strategy_id(f, {pi - 0.01}, 0.5));
}

TEST(CountStrategies, TheSameForEveryPermutationAndFailedTrialsIgnored) {
  const auto f = features({FeatureMetric::euclidean}, 0.0, std::numbers::pi);
  // Leader clustering in trial order gave 2 or 3 for such a chain over orderings.
  std::vector<std::vector<double>> v = {{0.2}, {0.55}, {0.9}, {1.25}, {2.5}, {3.0}};
  std::vector<bool> ok = {true, true, true, true, false, true};
  std::vector<std::size_t> order = {0, 1, 2, 3, 4, 5};
  const int expected = count_strategies(f, v, 0.5, &ok);
  EXPECT_EQ(expected, 4);  // cells of π/6: 0 (0.2), 1 (0.55, 0.9), 2 (1.25), 5 (3.0); 2.5 (cell 4) failed
  int permutations = 0;
  do {
    std::vector<std::vector<double>> pv;
    std::vector<bool> pok;
    for (auto i : order) {
      pv.push_back(v[i]);
      pok.push_back(ok[i]);
    }
    EXPECT_EQ(count_strategies(f, pv, 0.5, &pok), expected);
    ++permutations;
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(permutations, 720);
  // A failed trial in a cell no success occupies adds nothing; the same trial succeeding does.
  ok[4] = true;
  EXPECT_EQ(count_strategies(f, v, 0.5, &ok), 5);
  EXPECT_EQ(count_strategies(f, {}, 0.5), 0);
}

TEST(StrategyCeiling, CountsTheCellsAReachableRangeMeets) {
  const auto f = features({FeatureMetric::euclidean}, 0.0, std::numbers::pi);
  // The jump's reachable up-angles 0.23–2.43 rad: cells 0..4 at τ = 0.5, 0..2 at 2τ.
  EXPECT_EQ(strategy_ceiling(f, 0.5, {0.23}, {2.43}), 5);
  EXPECT_EQ(strategy_ceiling(f, 1.0, {0.23}, {2.43}), 3);
}

TEST(ExpectedRandomCount, MatchesTheClosedFormOfUniformCells) {
  // x uniform on [0, 1] → feature x on 4 equal cells, success everywhere: E[cells hit by k draws]
  // = 4 (1 − (3/4)^k).
  const auto f = features({FeatureMetric::euclidean}, 0.0, 1.0);
  Space space;
  space.params = {{"x", 0.0, 1.0, false}};
  const Outcome identity = [](const std::vector<double>& x) { return std::optional<std::vector<double>>(x); };
  const double e = expected_random_count(f, 0.25, space, identity, 5, 20000, 7);
  EXPECT_NEAR(e, 4.0 * (1.0 - std::pow(0.75, 5)), 0.03);
  // Failures (x > 0.5) remove their cells: 2 (1 − (3/4)^k).
  const Outcome half = [](const std::vector<double>& x) {
    return x[0] < 0.5 ? std::optional<std::vector<double>>(x) : std::nullopt;
  };
  EXPECT_NEAR(expected_random_count(f, 0.25, space, half, 5, 20000, 7), 2.0 * (1.0 - std::pow(0.75, 5)), 0.03);
}

TEST(TrialSuccess, ReadsTheTasksRuleFromTheResultInfo) {
  const base::Json info = {{"start_bar", {{"deterministic_success", false}, {"success_rate", 0.75}}}};
  EXPECT_TRUE(trial_success(nullptr, info));
  EXPECT_FALSE(trial_success({{"info", "/start_bar/deterministic_success"}}, info));
  EXPECT_TRUE(trial_success({{"info", "/start_bar/success_rate"}}, info));
  EXPECT_FALSE(trial_success({{"info", "/start_bar/success_rate"}, {"min", 0.8}}, info));
  EXPECT_FALSE(trial_success({{"info", "/missing"}}, info));
  EXPECT_THROW(trial_success({{"info", "no-slash"}}, info), base::UserError);
  EXPECT_THROW(trial_success(base::Json("cleared"), info), base::UserError);
}

TEST(StrategyIds, RejectWrongSizeNamingTheVector) {
  const auto f = features({FeatureMetric::euclidean, FeatureMetric::euclidean});
  try {
    strategy_ids(f, {{0.0, 1.0}, {0.5}}, 0.1);
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("feature vector 1 has 1 values but 2 features"), std::string::npos) << e.what();
  }
  EXPECT_THROW(strategy_ids(f, {}, -1.0), base::UserError);
  EXPECT_THROW(count_strategies(f, {}, 0.0), base::UserError);
  // A stage without features (its threshold is 0): every trial is the one strategy.
  EXPECT_EQ(strategy_ids({}, {{}, {}}, 0.0), (std::vector<std::int64_t>{0, 0}));
}

}  // namespace
}  // namespace podium::search
