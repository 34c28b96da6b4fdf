#include "bds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "landscape_model.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {
namespace {

SearchSetup unit_box(int dim, Json config) {
  SearchSetup s;
  Json space = Json::array();
  for (int i = 0; i < dim; ++i) space.push_back({{"name", "x" + std::to_string(i)}, {"low", 0.0}, {"high", 1.0}});
  s.space = Space::from_json(space, "space");
  s.features = Feature::list_from_json(
      Json::parse(R"([{"name": "f0", "low": 0, "high": 1}, {"name": "f1", "low": 0, "high": 1}])"), "features");
  s.config = std::move(config);
  s.seed = 11;
  return s;
}

Observation run(const Proposal& p, bool ok = true) {
  static const tasks::landscape::LandscapeModel model({"plateaus", 3, 2, 5});
  return {p.id, ok, ok ? std::vector<double>{model.objective(p.x)} : std::vector<double>{},
          ok ? model.feature(p.x) : std::vector<double>{}};
}

double min_pairwise_distance(const std::vector<Proposal>& ps) {
  double best = 1e300;
  for (std::size_t a = 0; a < ps.size(); ++a)
    for (std::size_t b = 0; b < a; ++b) {
      double s = 0;
      for (std::size_t i = 0; i < ps[a].x.size(); ++i) s += std::pow(ps[a].x[i] - ps[b].x[i], 2);
      best = std::min(best, std::sqrt(s));
    }
  return best;
}

TEST(Bds, BatchedProposalsAreDistinctPoints) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 5}}));
  std::vector<Observation> observations;
  for (const auto& p : search->ask(5)) observations.push_back(run(p));
  search->tell(observations);
  // 6 proposals span explore and diversity steps; pending points are believers, so none repeats.
  const auto batch = search->ask(6);
  ASSERT_EQ(batch.size(), 6u);
  EXPECT_GT(min_pairwise_distance(batch), 0.05);
}

// A result is modelled where it was measured: a task that looks results up at the nearest
// recorded point (tasks/pool) reports that point (Observation::x), and the GPs see it there.
TEST(Bds, AResultIsModelledWhereTheTrialRanNotWhereItWasAsked) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 2}}));
  const auto asked = search->ask(2);
  Observation elsewhere = run(asked[1]);
  elsewhere.x = {0.125, 0.875, 0.5};
  search->tell({run(asked[0]), elsewhere});
  const Json told = search->save().at("told");
  ASSERT_EQ(told.size(), 2u);
  EXPECT_EQ(told[0].at("u"), Json(asked[0].x)) << "the unit box: u is x";
  EXPECT_EQ(told[1].at("u"), Json({0.125, 0.875, 0.5}));
  Observation short_x = run(search->ask(1).at(0));
  short_x.x = {0.5};
  EXPECT_THROW(search->tell({short_x}), base::UserError);
}

// The obstacle jump's Stage 1 as it started: one success, one failure, one initial sample still
// running. Fitted on that one success, maximum likelihood can explain the feature as noise, which
// leaves σ flat over the box, and the success-weighted exploration step proposed that success
// again (6 of these 20 seeds did). The GPs keep their default hyperparameters until they have more
// points than hyperparameters.
TEST(Bds, AnExplorationStepDoesNotProposeAnEvaluatedPointAgain) {
  SearchSetup s;
  Json space = Json::array();
  for (const char* n : {"wx", "wy", "wz"}) space.push_back({{"name", n}, {"low", -4.0}, {"high", 4.0}});
  s.space = Space::from_json(space, "space");
  s.features = Feature::list_from_json(Json::parse(R"([{"name": "up", "low": 0, "high": 3.14159}])"), "features");
  s.config = {{"initial_samples", 3}, {"explore_until", 6}};
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    s.seed = seed;
    auto search = make_search("bds", s);
    const auto first = search->ask(2);
    search->tell({{first[0].id, true, {0.25}, {0.49}}});
    ASSERT_EQ(search->ask(1).at(0).info.at("step"), "initial");
    search->tell({{first[1].id, false, {}, {}}});
    const auto next = search->ask(1).at(0);
    ASSERT_EQ(next.info.at("step"), "explore");
    double d2 = 0.0;
    for (std::size_t i = 0; i < 3; ++i) d2 += std::pow((next.x[i] - first[0].x[i]) / 8.0, 2);
    EXPECT_GT(std::sqrt(d2), 0.05) << "seed " << seed;
  }
}

TEST(Search, WhereATrialRanIsReadFromItsResultInfo) {
  EXPECT_EQ(evaluated_params(Json::parse(R"({"evaluated_params": [0.5, 2]})")), (std::vector<double>{0.5, 2.0}));
  EXPECT_TRUE(evaluated_params(Json::object()).empty());
  EXPECT_TRUE(evaluated_params(Json()).empty());
  EXPECT_TRUE(evaluated_params(Json::parse(R"({"evaluated_params": [0.5, "x"]})")).empty());
}

TEST(Bds, FailedTrialsAreKeptOutAndNotProposedAgain) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 3}, {"fit_min_points", 3}}));
  for (const auto& p : search->ask(3)) search->tell({run(p)});
  std::vector<Proposal> after;
  for (int t = 0; t < 8; ++t) {
    const auto p = search->ask(1).at(0);
    after.push_back(p);
    search->tell({run(p, false)});
  }
  EXPECT_GT(min_pairwise_distance(after), 1e-3);
  EXPECT_EQ(search->save().at("fitted_on"), 3);  // only the successful trials were fitted
}

TEST(Bds, ExploresUntilTheScheduleSaysThenTakesDiversitySteps) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 2}, {"explore_until", 5}, {"stall", 0}}));
  std::vector<std::string> steps;
  for (int t = 0; t < 8; ++t) {
    const auto p = search->ask(1).at(0);
    steps.push_back(p.info.at("step"));
    search->tell({run(p)});
  }
  EXPECT_EQ(steps, (std::vector<std::string>{"initial", "initial", "explore", "explore", "explore", "diversity", "diversity",
                                             "diversity"}));
}

// Diversity steps whose results repeat a known feature vector stall; after `stall` of them BDS
// explores for up to `stall_explore` steps, and goes back to diversity steps as soon as an
// exploration step finds a new strategy.
TEST(Bds, StalledDiversityStepsFallBackToExploration) {
  auto search = make_search(
      "bds",
      unit_box(3, {{"initial_samples", 2}, {"explore_until", 0}, {"stall", 2}, {"stall_explore", 2}, {"direct_evals", 200}}));
  std::vector<std::string> steps;
  for (int t = 0; t < 12; ++t) {
    const auto p = search->ask(1).at(0);
    steps.push_back(p.info.at("step"));
    // Every result repeats the first strategy except from the 3rd exploration step on, where each
    // point is its own strategy.
    const int explored = static_cast<int>(std::count(steps.begin(), steps.end(), "explore"));
    const bool fresh = p.info.at("step") == "explore" && explored >= 3;
    search->tell({{p.id, true, {0.0}, fresh ? std::vector<double>{p.x[0], p.x[1]} : std::vector<double>{0.5, 0.5}}});
  }
  EXPECT_EQ(steps, (std::vector<std::string>{"initial", "initial", "diversity", "diversity", "explore", "explore", "diversity",
                                             "diversity", "explore", "diversity", "diversity", "explore"}));
}

TEST(Bds, MaximinInitialDesignSpreadsTheInitialSamples) {
  auto spread = [](const char* design) {
    auto search = make_search("bds", unit_box(3, {{"initial_samples", 8}, {"initial_design", design}}));
    return min_pairwise_distance(search->ask(8));
  };
  EXPECT_GT(spread("maximin"), 1.5 * spread("random"));
}

TEST(Bds, ExplorationBonusKeepsDiversityStepsDistinctAndInsideTheBox) {
  auto search = make_search(
      "bds", unit_box(3, {{"initial_samples", 3}, {"explore_until", 0}, {"stall", 0}, {"ucb_beta", 0.1}, {"direct_evals", 200}}));
  std::vector<Proposal> all;
  for (int t = 0; t < 8; ++t) {
    const auto p = search->ask(1).at(0);
    for (double v : p.x) EXPECT_TRUE(v >= 0.0 && v <= 1.0);
    all.push_back(p);
    search->tell({run(p)});
  }
  EXPECT_EQ(all.back().info.at("step"), "diversity");
  EXPECT_GT(min_pairwise_distance(all), 1e-3);
}

// Three of four feature combinations seen, in three quadrants: the "new combination" acquisition
// (bds.h, the default for quantised features) must aim at the quadrant where the GPs predict the
// fourth. Run on a Euclidean and on an angular first feature whose two values straddle the 0/2π seam.
TEST(Bds, DiversityStepAimsAtTheUnseenCombinationOfObservedLevels) {
  for (const std::string metric : {"euclidean", "angular"}) {
    SearchSetup setup = unit_box(2, {{"explore_until", 0}, {"stall", 0}});
    const double low0 = metric == "angular" ? 6.1 : 0.2, high0 = metric == "angular" ? 0.4 : 0.8;
    setup.features = Feature::list_from_json(
        Json::array({{{"name", "f0"}, {"low", 0.0}, {"high", 2.0 * std::numbers::pi}, {"metric", metric}, {"quantised", true}},
                     {{"name", "f1"}, {"low", 0.0}, {"high", 1.0}, {"quantised", true}}}),
        "features");
    auto search = make_search("bds", setup);
    EXPECT_EQ(dynamic_cast<BayesianDiversitySearch&>(*search).acquisition(), "new_combination");
    Json state = search->save();
    state["told"] = Json::array();
    std::uint64_t id = 0;
    const std::vector<double> grid = {0.05, 0.2, 0.35, 0.65, 0.8, 0.95};
    for (double x0 : grid)
      for (double x1 : grid)
        if (x0 < 0.5 || x1 < 0.5)
          state["told"].push_back(
              {{"id", id++}, {"u", {x0, x1}}, {"ok", true}, {"features", {x0 > 0.5 ? high0 : low0, x1 > 0.5 ? 0.8 : 0.2}}});
    state["next_id"] = id;
    search->load(state);
    const auto p = search->ask(1).at(0);
    EXPECT_EQ(p.info.at("step"), "diversity") << metric;
    EXPECT_GT(p.x[0], 0.5) << metric;
    EXPECT_GT(p.x[1], 0.5) << metric;
  }
}

// Continuous features, smooth in x, observed at a few points of the box (with or without
// measurement noise): the default diversity acquisition is eq. 3.7 and varies over the box.
// Before, "new_combination" on one continuous feature was identically 0 (every observed value a
// level, every level a strategy), so DIRECT returned the box's centre.
TEST(Bds, DefaultAcquisitionVariesOverTheBoxForContinuousFeatures) {
  for (int nf : {1, 2})
    for (double noise : {0.0, 0.05})
      for (const std::string acquisition : {"auto", "new_combination"}) {
        const std::string label = std::to_string(nf) + "-D, noise " + std::to_string(noise) + ", " + acquisition;
        SearchSetup setup = unit_box(2, {{"initial_samples", 1}, {"acquisition", acquisition}});
        Json fs = Json::array();
        for (int j = 0; j < nf; ++j) fs.push_back({{"name", "f" + std::to_string(j)}, {"low", 0.0}, {"high", 1.0}});
        setup.features = Feature::list_from_json(fs, "features");
        BayesianDiversitySearch search(setup, "search");
        if (acquisition == "auto") {
          EXPECT_EQ(search.acquisition(), "expected_distance") << label;
        }
        base::Rng rng(3);
        for (int t = 0; t < 6; ++t) {
          const auto p = search.ask(1).at(0);
          std::vector<double> f = {0.5 * (p.x[0] + p.x[1]), p.x[0] * p.x[1]};
          f.resize(static_cast<std::size_t>(nf));
          for (auto& v : f) v += rng.normal(0.0, noise);
          search.tell({{p.id, true, {0.0}, f}});
        }
        std::vector<Eigen::VectorXd> grid;
        for (double a = 0.0; a <= 1.0; a += 0.125)
          for (double b = 0.0; b <= 1.0; b += 0.125) grid.push_back(Eigen::Vector2d(a, b));
        const auto values = search.diversity_values(grid);
        const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
        EXPECT_GT(*hi - *lo, 0.1 * std::abs(*hi)) << label << ": from " << *lo << " to " << *hi;
      }
}

// Eq. 3.7 by Monte Carlo against its closed form for one feature and one target: for
// X ~ N(μ, σ²), E|X − t| = σ √(2/π) exp(−δ²/2σ²) + δ (1 − 2 Φ(−δ/σ)), δ = μ − t.
TEST(Bds, ExpectedDistanceMatchesTheClosedFormForOneTarget) {
  const auto features = Feature::list_from_json(Json::parse(R"([{"name": "f", "low": 0, "high": 1}])"), "features");
  base::Rng rng(5);
  Eigen::MatrixXd eps(200000, 1);
  for (Eigen::Index s = 0; s < eps.rows(); ++s) eps(s, 0) = rng.normal();
  for (const auto& [mu, sigma, t] :
       std::vector<std::tuple<double, double, double>>{{0.3, 0.2, 0.1}, {0.5, 0.05, 0.5}, {0.9, 0.3, 0.2}}) {
    const double delta = mu - t;
    const double phi = 0.5 * std::erfc(delta / sigma / std::numbers::sqrt2);  // Φ(−δ/σ)
    const double exact =
        sigma * std::sqrt(2.0 / std::numbers::pi) * std::exp(-delta * delta / (2 * sigma * sigma)) + delta * (1.0 - 2.0 * phi);
    // 200 000 draws: the standard error is below σ/400.
    EXPECT_NEAR(expected_nearest_distance(features, {mu}, {sigma}, {{t}}, eps), exact, sigma / 100) << mu << " " << t;
  }
}

// A diversity step whose result lies within the strategy threshold of a known strategy (not
// equal to it, as measurement noise makes it) is no new strategy: two in a row stall the
// diversity steps and an exploration step follows.
TEST(Bds, StallFiresOnARepeatWithinTheThreshold) {
  SearchSetup setup = unit_box(2, {{"initial_samples", 2}, {"explore_until", 0}, {"stall", 2}, {"direct_evals", 100}});
  setup.strategy_threshold = 0.1;
  auto search = make_search("bds", setup);
  std::vector<std::string> steps;
  for (int t = 0; t < 5; ++t) {
    const auto p = search->ask(1).at(0);
    steps.push_back(p.info.at("step"));
    const std::vector<double> f = t == 1 ? std::vector<double>{0.8, 0.8} : std::vector<double>{0.2 + 0.03 * t, 0.2 - 0.02 * t};
    search->tell({{p.id, true, {0.0}, f}});
  }
  EXPECT_EQ(steps, (std::vector<std::string>{"initial", "initial", "diversity", "diversity", "explore"}));
}

// Algorithm 1 as written: random initial samples, then t % (N_exp + N_opt) < N_exp explores.
TEST(Bds, ThesisScheduleAlternatesThreeExplorationAndThreeDiversitySteps) {
  auto search = make_search("bds", unit_box(3, {{"schedule", "thesis"}, {"initial_samples", 2}, {"direct_evals", 100}}));
  std::vector<std::string> steps;
  for (int t = 0; t < 11; ++t) {
    const auto p = search->ask(1).at(0);
    steps.push_back(p.info.at("step"));
    search->tell({run(p)});
  }
  EXPECT_EQ(steps, (std::vector<std::string>{"initial", "initial", "explore", "explore", "explore", "diversity", "diversity",
                                             "diversity", "explore", "explore", "explore"}));
}

// "Failed samples" (bds.h) on a 1-D box whose feature is x itself and whose trials fail for
// x ≥ 0.6 (a finished failure still reports its feature). Told: successes at 0, 0.1, .., 0.4 and
// failures at 0.6, 0.7, .., 1.0.
BayesianDiversitySearch one_sided_failures(const std::string& failures) {
  SearchSetup setup = unit_box(1, {{"initial_samples", 10}, {"failures", failures}, {"direct_evals", 200}});
  setup.features = Feature::list_from_json(Json::parse(R"([{"name": "f", "low": 0, "high": 1}])"), "features");
  BayesianDiversitySearch search(setup, "search");
  const auto proposals = search.ask(10);
  const std::vector<double> xs = {0.0, 0.1, 0.2, 0.3, 0.4, 0.6, 0.7, 0.8, 0.9, 1.0};
  std::vector<Observation> told;
  for (std::size_t i = 0; i < xs.size(); ++i) told.push_back({proposals[i].id, true, {0.0}, {xs[i]}, xs[i] < 0.6});
  // The proposals were the initial design; what the search believes comes from the told values.
  search.load([&] {
    Json state = search.save();
    for (std::size_t i = 0; i < xs.size(); ++i) state["pending"][i]["u"] = Json::array({xs[i]});
    return state;
  }());
  search.tell(told);
  return search;
}

// With failures modelled, the diversity acquisition is weighed by the success probability: its
// maximum lies where trials succeed or at the edge of what is known, never inside the region
// where every told trial failed. Read literally ("ignore"), the failed features are diversity
// targets like any and the acquisition does not see the failures.
TEST(Bds, FailedSamplesWeighTheDiversityAcquisitionByTheSuccessProbability) {
  std::vector<Eigen::VectorXd> grid;
  for (int k = 0; k <= 20; ++k) grid.push_back(Eigen::VectorXd::Constant(1, k / 20.0));
  auto modelled = one_sided_failures("model");
  const auto values = modelled.diversity_values(grid);
  const double best_inside = *std::max_element(values.begin() + 13, values.end());     // x ≥ 0.65
  const double best_outside = *std::max_element(values.begin(), values.begin() + 12);  // x ≤ 0.55
  EXPECT_LT(best_inside, 0.5 * best_outside) << "inside " << best_inside << ", outside " << best_outside;
  // The next proposal (a diversity step: 10 points told) stays out of the failed region.
  const auto next = modelled.ask(1).at(0);
  EXPECT_EQ(next.info.at("step"), "diversity");
  EXPECT_LT(next.x[0], 0.6);
  // Fitted on the 5 successes only; the success model on all 10 told trials.
  const Json state = modelled.save();
  EXPECT_EQ(state.at("fitted_on"), 5);
  EXPECT_EQ(state.at("success_fitted_on"), 10);
  auto literal = one_sided_failures("ignore");
  EXPECT_EQ(literal.save().at("fitted_on"), 0);  // fitted when it first proposes
  literal.diversity_values(grid);
  EXPECT_EQ(literal.save().at("fitted_on"), 10);
}

// While every told trial succeeded, modelling failures changes nothing: p ≡ 1, the same GPs.
TEST(Bds, WithoutFailuresTheModelledAndLiteralReadingsAgree) {
  std::vector<std::vector<double>> proposed[2];
  for (int k = 0; k < 2; ++k) {
    auto search = make_search(
        "bds",
        unit_box(
            3, {{"initial_samples", 3}, {"explore_until", 6}, {"direct_evals", 100}, {"failures", k == 0 ? "model" : "ignore"}}));
    for (int t = 0; t < 9; ++t) {
      const auto p = search->ask(1).at(0);
      proposed[k].push_back(p.x);
      search->tell({run(p)});
    }
  }
  EXPECT_EQ(proposed[0], proposed[1]);
}

// The success model's state survives save/load: a resumed search proposes what the original would.
TEST(Bds, ResumedSearchWithFailuresProposesTheSame) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 3}, {"explore_until", 5}, {"direct_evals", 100}}));
  for (int t = 0; t < 7; ++t) {
    const auto p = search->ask(1).at(0);
    Observation o = run(p);
    o.success = p.x[0] < 0.5;
    search->tell({o});
  }
  auto resumed = make_search("bds", unit_box(3, {{"initial_samples", 3}, {"explore_until", 5}, {"direct_evals", 100}}));
  resumed->load(search->save());
  for (int t = 0; t < 2; ++t) {
    const auto a = search->ask(1).at(0), b = resumed->ask(1).at(0);
    EXPECT_EQ(a.x, b.x);
    Observation o = run(a);
    o.success = a.x[0] < 0.5;
    search->tell({o});
    o.id = b.id;
    resumed->tell({o});
  }
}

}  // namespace
}  // namespace podium::search
