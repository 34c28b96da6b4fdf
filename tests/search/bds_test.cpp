#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "landscape_model.h"
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

TEST(Bds, FailedTrialsAreKeptOutAndNotProposedAgain) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 3}}));
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
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 2}, {"explore_until", 0}, {"stall", 2},
                                                {"stall_explore", 2}, {"direct_evals", 200}}));
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
  EXPECT_EQ(steps, (std::vector<std::string>{"initial", "initial", "diversity", "diversity", "explore", "explore",
                                             "diversity", "diversity", "explore", "diversity", "diversity", "explore"}));
}

TEST(Bds, MaximinInitialDesignSpreadsTheInitialSamples) {
  auto spread = [](const char* design) {
    auto search = make_search("bds", unit_box(3, {{"initial_samples", 8}, {"initial_design", design}}));
    return min_pairwise_distance(search->ask(8));
  };
  EXPECT_GT(spread("maximin"), 1.5 * spread("random"));
}

TEST(Bds, ExplorationBonusKeepsDiversityStepsDistinctAndInsideTheBox) {
  auto search = make_search("bds", unit_box(3, {{"initial_samples", 3}, {"explore_until", 0}, {"stall", 0}, {"ucb_beta", 0.1},
                                                {"direct_evals", 200}}));
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
// (bds.h) must aim at the quadrant where the GPs predict the fourth. Run on a Euclidean and on an
// angular first feature whose two values straddle the 0/2π seam.
TEST(Bds, DiversityStepAimsAtTheUnseenCombinationOfObservedLevels) {
  for (const std::string metric : {"euclidean", "angular"}) {
    SearchSetup setup = unit_box(2, {{"explore_until", 0}, {"stall", 0}});
    const double low0 = metric == "angular" ? 6.1 : 0.2, high0 = metric == "angular" ? 0.4 : 0.8;
    setup.features = Feature::list_from_json(
        Json::array({{{"name", "f0"}, {"low", 0.0}, {"high", 2.0 * std::numbers::pi}, {"metric", metric}},
                     {{"name", "f1"}, {"low", 0.0}, {"high", 1.0}}}),
        "features");
    auto search = make_search("bds", setup);
    Json state = search->save();
    state["told"] = Json::array();
    std::uint64_t id = 0;
    const std::vector<double> grid = {0.05, 0.2, 0.35, 0.65, 0.8, 0.95};
    for (double x0 : grid)
      for (double x1 : grid)
        if (x0 < 0.5 || x1 < 0.5)
          state["told"].push_back({{"id", id++}, {"u", {x0, x1}}, {"ok", true},
                                   {"features", {x0 > 0.5 ? high0 : low0, x1 > 0.5 ? 0.8 : 0.2}}});
    state["next_id"] = id;
    search->load(state);
    const auto p = search->ask(1).at(0);
    EXPECT_EQ(p.info.at("step"), "diversity") << metric;
    EXPECT_GT(p.x[0], 0.5) << metric;
    EXPECT_GT(p.x[1], 0.5) << metric;
  }
}

}  // namespace
}  // namespace podium::search
