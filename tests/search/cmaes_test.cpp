#include <gtest/gtest.h>

#include "podium/base/error.h"
#include "podium/search/search.h"

namespace podium::search {
namespace {

SearchSetup box(int dim, Json config) {
  SearchSetup s;
  Json space = Json::array();
  for (int i = 0; i < dim; ++i) space.push_back({{"name", "x" + std::to_string(i)}, {"low", -5.0}, {"high", 5.0}});
  s.space = Space::from_json(space, "space");
  s.config = std::move(config);
  s.seed = 3;
  return s;
}

TEST(Cmaes, MaximisesAShiftedQuadraticTo1e10) {
  auto search = make_search("cmaes", box(5, {{"min_step", 0.0}}));  // no step-size stop: on to 1e-10
  double best = -1e300;
  for (int evals = 0; evals < 3000;)
    for (const auto& p : search->ask(4)) {
      double f = 0;
      for (double v : p.x) f -= (v - 1.5) * (v - 1.5);
      best = std::max(best, f);
      search->tell({{p.id, true, {f}, {}}});
      ++evals;
    }
  EXPECT_GT(best, -1e-10);
}

TEST(Cmaes, WaitsForTheWholeGenerationBeforeProposingMore) {
  // 5-D: λ = 4 + ⌊3 ln 5⌋ = 8.
  auto search = make_search("cmaes", box(5, {{"direction", "minimize"}}));
  const auto first = search->ask(100);
  ASSERT_EQ(first.size(), 8u);
  EXPECT_TRUE(search->ask(1).empty());
  for (std::size_t k = 0; k + 1 < first.size(); ++k) search->tell({{first[k].id, k % 3 != 0, {static_cast<double>(k)}, {}}});
  EXPECT_TRUE(search->ask(1).empty());
  search->tell({{first.back().id, false, {}, {}}});  // failures rank last and do not stall
  const auto second = search->ask(2);
  ASSERT_EQ(second.size(), 2u);
  EXPECT_EQ(second[0].id, 8u);
  EXPECT_EQ(second[0].info.at("generation"), 1);
}

// Runs a 2-D search (λ = 6, mean at a corner-ish start) on a quadratic until it proposes nothing
// or `max_evals` pass; returns the evaluations it took.
int run_until_stop(Search& search, int max_evals) {
  int evals = 0;
  while (evals < max_evals) {
    const auto proposals = search.ask(6);
    if (proposals.empty()) break;
    for (const auto& p : proposals) {
      const double f = (p.x[0] - 1.0) * (p.x[0] - 1.0) + 3.0 * (p.x[1] + 2.0) * (p.x[1] + 2.0);
      search.tell({{p.id, true, {f}, {}}});
      ++evals;
    }
  }
  return evals;
}

Json two_d(double min_step) {
  return {{"direction", "minimize"}, {"population", 6}, {"x0", {{"x0", 4.0}, {"x1", 3.0}}}, {"min_step", min_step}};
}

TEST(Cmaes, StopsOnceEveryStepSizeIsUnderMinStepOfTheRange) {
  auto search = make_search("cmaes", box(2, two_d(0.01)));
  const int evals = run_until_stop(*search, 100000);
  ASSERT_LT(evals, 100000);  // it stopped by itself
  EXPECT_EQ(evals % 6, 0);   // after a whole generation
  const Json state = search->save();
  EXPECT_TRUE(state.at("stopped").get<bool>());
  for (const Json& step : state.at("step_sizes")) EXPECT_LT(step.get<double>(), 0.01);
  EXPECT_TRUE(search->ask(6).empty());
  // Converged where the optimum is: within a few step sizes (of the range, 10) of (1, −2).
  const Json& mean = state.at("mean");
  EXPECT_NEAR(mean[0].get<double>() * 10.0 - 5.0, 1.0, 0.3);
  EXPECT_NEAR(mean[1].get<double>() * 10.0 - 5.0, -2.0, 0.3);
  // The result in parameter units: the mean (range 10, low −5), step sizes of the range, and the
  // covariance σ²·C scaled by the ranges (its diagonal the step sizes squared).
  const Json& result = state.at("result");
  EXPECT_EQ(result.at("mean").at("x0").get<double>(), mean[0].get<double>() * 10.0 - 5.0);
  EXPECT_EQ(result.at("mean").at("x1").get<double>(), mean[1].get<double>() * 10.0 - 5.0);
  EXPECT_TRUE(result.at("stopped").get<bool>());
  EXPECT_EQ(result.at("generations").get<int>(), evals / 6);
  for (int i = 0; i < 2; ++i) {
    const std::string name = "x" + std::to_string(i);
    const double step = state.at("step_sizes")[static_cast<std::size_t>(i)].get<double>() * 10.0;
    EXPECT_NEAR(result.at("step_sizes").at(name).get<double>(), step, 1e-12);
    EXPECT_NEAR(result.at("covariance")[static_cast<std::size_t>(i)][static_cast<std::size_t>(i)].get<double>(), step * step,
                1e-12);
  }
  EXPECT_EQ(result.at("covariance")[0][1], result.at("covariance")[1][0]);
  // The generation before the stop was still above the bound: replay it and check.
  auto replay = make_search("cmaes", box(2, two_d(0.01)));
  ASSERT_EQ(run_until_stop(*replay, evals - 6), evals - 6);
  bool above = false;
  const Json before = replay->save();
  EXPECT_FALSE(before.at("stopped").get<bool>());
  for (const Json& step : before.at("step_sizes")) above = above || step.get<double>() >= 0.01;
  EXPECT_TRUE(above);
  // A loaded stopped search stays stopped.
  auto loaded = make_search("cmaes", box(2, two_d(0.01)));
  loaded->load(state);
  EXPECT_TRUE(loaded->ask(6).empty());
  // A coarser bound stops sooner; 0 never stops (the same search runs on past the stop).
  auto coarse = make_search("cmaes", box(2, two_d(0.1)));
  EXPECT_LT(run_until_stop(*coarse, 100000), evals);
  auto never = make_search("cmaes", box(2, two_d(0.0)));
  EXPECT_EQ(run_until_stop(*never, evals + 60), evals + 60);
}

TEST(Cmaes, RejectsAMinStepOutsideZeroToOne) {
  try {
    make_search("cmaes", box(2, {{"min_step", 1.5}}), "stages[2].search");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("stages[2].search.config.min_step"), std::string::npos) << e.what();
  }
}

TEST(Cmaes, RejectsX0OutsideTheBoxNamingIt) {
  try {
    make_search("cmaes", box(2, {{"x0", {{"x0", 0.0}, {"x1", 9.0}}}}), "stages[1].search");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("stages[1].search.config.x0.x1: 9.0 is not in [-5, 5]"), std::string::npos) << e.what();
  }
  try {
    make_search("cmaes", box(2, {{"x0", {{"x0", 0.0}, {"x2", 1.0}}}}), "stages[1].search");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("stages[1].search.config.x0.x1: missing (required)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace podium::search
