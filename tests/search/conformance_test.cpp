// The conformance suite every search algorithm passes (docs/style.md "search/"): proposals inside the
// bounds, unknown ids and unknown options rejected clearly, save→load→ask identical, and a
// campaign killed and resumed after every step proposes what an uninterrupted one does.
// Trials are evaluated on the real analytic landscape of tasks/landscape.
#include <gtest/gtest.h>

#include "landscape_model.h"
#include "podium/base/error.h"
#include "podium/search/search.h"

namespace podium::search {
namespace {

using tasks::landscape::LandscapeModel;
using tasks::landscape::LandscapeOptions;

SearchSetup conformance_setup(const std::string& algorithm) {
  SearchSetup s;
  s.space = Space::from_json(Json::parse(R"([{"name": "a", "low": -1, "high": 2},
                                             {"name": "b", "low": 0, "high": 1},
                                             {"name": "n", "low": 0, "high": 10, "integer": true}])"),
                             "space");
  s.features = Feature::list_from_json(Json::parse(R"([{"name": "f0", "low": 0, "high": 1},
                                                        {"name": "f1", "low": 0, "high": 1}])"),
                                       "features");
  s.seed = 42;
  s.inputs = Json::parse(R"([{"trial_index": 3, "params": {"a": 0.5, "b": 0.2, "n": 4}, "objectives": [-0.1],
                               "features": [0.2, 0.7], "artifacts": {"policy": "/runs/3/policy.pt"}, "strategy": 0},
                              {"trial_index": 8, "params": {"a": 1.5, "b": 0.9, "n": 7}, "objectives": [-0.3],
                               "features": [0.8, 0.1], "artifacts": {}, "strategy": 1}])");
  // Small inner budgets keep the suite fast; the algorithms are the same.
  if (algorithm == "bds") s.config = {{"initial_samples", 3}, {"direct_evals", 200}, {"explore_candidates", 64}};
  return s;
}

// Evaluates a proposal on a 3-D plateau landscape; every 5th trial fails.
Observation evaluate(const Proposal& p) {
  static const LandscapeModel model(LandscapeOptions{"plateaus", 3, 7, 5});
  const std::vector<double> u = {(p.x[0] + 1.0) / 3.0, p.x[1], p.x[2] / 10.0};
  Observation o;
  o.id = p.id;
  o.ok = p.id % 5 != 4;
  if (o.ok) {
    o.features = model.feature(u);
    o.objectives = {model.objective(u)};
  }
  return o;
}

class SearchConformance : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<Search> make() const { return make_search(GetParam(), conformance_setup(GetParam()), "stages[0].search"); }
};

// One step of a campaign: ask two, tell them in reverse order (completion order differs from ask order).
std::vector<Proposal> step(Search& search) {
  auto proposals = search.ask(2);
  std::vector<Observation> observations;
  for (auto it = proposals.rbegin(); it != proposals.rend(); ++it) observations.push_back(evaluate(*it));
  search.tell(observations);
  return proposals;
}

TEST_P(SearchConformance, ProposalsStayInsideBoundsWithWholeIntegers) {
  auto search = make();
  const SearchSetup setup = conformance_setup(GetParam());
  std::set<std::uint64_t> ids;
  for (int s = 0; s < 12; ++s)
    for (const auto& p : step(*search)) {
      EXPECT_TRUE(setup.space.contains(p.x)) << GetParam() << " proposal " << p.id;
      EXPECT_EQ(p.x[2], std::round(p.x[2])) << "integer parameter n is " << p.x[2];
      EXPECT_TRUE(ids.insert(p.id).second) << "id " << p.id << " proposed twice";
    }
  EXPECT_EQ(search->name(), GetParam());
}

TEST_P(SearchConformance, RejectsUnknownAndRepeatedIds) {
  auto search = make();
  const auto proposals = search->ask(1);
  ASSERT_EQ(proposals.size(), 1u);
  Observation unknown;
  unknown.id = 999;
  EXPECT_THROW(
      {
        try {
          search->tell({unknown});
        } catch (const base::UserError& e) {
          EXPECT_NE(std::string(e.what()).find("999, which is not a pending proposal"), std::string::npos) << e.what();
          throw;
        }
      },
      base::UserError);
  search->tell({evaluate(proposals[0])});
  EXPECT_THROW(search->tell({evaluate(proposals[0])}), base::UserError);
}

TEST_P(SearchConformance, RejectsUnknownOptionNamingItsPath) {
  SearchSetup setup = conformance_setup(GetParam());
  setup.config["no_such_option"] = 1;
  try {
    make_search(GetParam(), setup, "stages[2].search");
    FAIL() << "an unknown option was accepted";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("stages[2].search.config"), std::string::npos) << e.what();
  }
}

void expect_same(const std::vector<Proposal>& a, const std::vector<Proposal>& b, const std::string& where) {
  ASSERT_EQ(a.size(), b.size()) << where;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << where;
    EXPECT_EQ(a[i].x, b[i].x) << where << " proposal " << a[i].id;
    EXPECT_EQ(a[i].context, b[i].context) << where;
  }
}

TEST_P(SearchConformance, SaveLoadAskProposesIdentically) {
  auto original = make();
  for (int s = 0; s < 5; ++s) step(*original);
  original->ask(1);  // leave one pending
  const std::string saved = original->save().dump();
  auto restored = make();
  restored->load(Json::parse(saved));
  EXPECT_EQ(restored->save().dump(), saved);
  expect_same(original->ask(3), restored->ask(3), "after load");
}

TEST_P(SearchConformance, KilledAndResumedCampaignMatchesUninterruptedRun) {
  auto uninterrupted = make();
  std::vector<Proposal> expected, resumed;
  for (int s = 0; s < 10; ++s)
    for (auto& p : step(*uninterrupted)) expected.push_back(p);

  // Kill after every step: only the stored JSON text survives, a fresh process loads it.
  std::string stored = make()->save().dump();
  for (int s = 0; s < 10; ++s) {
    auto search = make();
    search->load(Json::parse(stored));
    for (auto& p : step(*search)) resumed.push_back(p);
    stored = search->save().dump();
  }
  expect_same(expected, resumed, "resumed campaign");
}

INSTANTIATE_TEST_SUITE_P(AllAlgorithms, SearchConformance, ::testing::ValuesIn(algorithm_names()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace podium::search
