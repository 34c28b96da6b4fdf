#include <gtest/gtest.h>

#include <numbers>

#include "podium/base/error.h"
#include "podium/search/search.h"

namespace podium::search {
namespace {

SearchSetup stage2(int trials_per_input) {
  SearchSetup s;
  s.space = Space::from_json(Json::parse(R"([{"name": "a", "low": 0, "high": 1}, {"name": "b", "low": 0, "high": 1}])"), "space");
  s.features = Feature::list_from_json(
      Json::parse(R"([{"name": "tilt", "low": 0, "high": 3.2, "metric": "angular"}, {"name": "twist", "low": 0, "high": 3.2}])"),
      "features");
  s.config = {{"trials_per_input", trials_per_input}};
  s.inputs = Json::parse(R"([{"trial_index": 4, "params": {"a": 0.1, "b": 0.2}, "objectives": [1], "features": [0.3, 1.0],
                               "artifacts": {"policy": "/runs/4/policy.pt"}, "strategy": 0},
                              {"trial_index": 9, "params": {"a": 0.7, "b": 0.8}, "objectives": [1], "features": [2.0, 0.1],
                               "artifacts": {}, "strategy": 1}])");
  return s;
}

TEST(NovelPolicySeeking, ContextCarriesFeaturesFoundSoFarForThatInput) {
  auto search = make_search("novel_policy", stage2(2));
  const auto first = search->ask(8);
  ASSERT_EQ(first.size(), 2u);  // one running trial per input
  EXPECT_EQ(first[0].x, (std::vector<double>{0.1, 0.2}));
  EXPECT_EQ(first[0].input, 0u);  // a stage handing one input per trial hands this one
  EXPECT_EQ(first[1].input, 1u);
  EXPECT_EQ(first[0].context.at("novelty").at("features"), Json::parse("[[0.3, 1.0]]"));
  EXPECT_DOUBLE_EQ(first[0].context.at("novelty").at("d_threshold").get<double>(), std::numbers::pi / 2);  // eq. 3.12
  EXPECT_EQ(first[0].context.at("warm_start"), "/runs/4/policy.pt");
  EXPECT_TRUE(first[1].context.at("warm_start").is_null());

  search->tell({{first[0].id, true, {0.5}, {1.2, 2.0}}});
  const auto second = search->ask(8);
  ASSERT_EQ(second.size(), 1u);  // input 1 is still running
  EXPECT_EQ(second[0].context.at("novelty").at("features"), Json::parse("[[0.3, 1.0], [1.2, 2.0]]"));
  search->tell({{second[0].id, true, {0.5}, {2.5, 0.0}}, {first[1].id, false, {}, {}}});
  const auto third = search->ask(8);
  ASSERT_EQ(third.size(), 1u);  // input 0 is done (2 trials); the failure used up one of input 1's
  EXPECT_EQ(third[0].context.at("novelty").at("features"), Json::parse("[[2.0, 0.1]]"));
  EXPECT_EQ(third[0].input, 1u);
  search->tell({{third[0].id, true, {0.5}, {0.0, 0.0}}});
  EXPECT_TRUE(search->ask(8).empty());
}

// The jumps' Stage 1 feature is 1-D, Stage 2's 3-D: such an input is handed over, its feature
// left out of the context (the task reads the input trial itself).
TEST(NovelPolicySeeking, TakesAnInputWhoseFeatureHasAnotherSize) {
  SearchSetup s = stage2(1);
  s.inputs[0]["features"] = {0.3};
  auto search = make_search("novel_policy", s);
  const auto first = search->ask(8);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].context.at("novelty").at("features"), Json::array());
  EXPECT_EQ(first[1].context.at("novelty").at("features"), Json::parse("[[2.0, 0.1]]"));
}

TEST(NovelPolicySeeking, RejectsInputsOutsideTheSpaceNamingThePath) {
  SearchSetup s = stage2(2);
  s.inputs[1]["params"]["b"] = 3.0;
  try {
    make_search("novel_policy", s, "stages[1].search");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("stages[1].search.inputs[1].params.b: 3.0 is not a number in [0.0, 1.0]"),
              std::string::npos)
        << e.what();
  }
  s.inputs = Json::array();
  EXPECT_THROW(make_search("novel_policy", s), base::UserError);
}

// At submit the inputs do not exist yet (they are resolved when the stage starts): the check
// takes the config and whether the stage declares inputs.
TEST(NovelPolicySeeking, IsSubmittableBeforeItsInputsExist) {
  SearchSetup s = stage2(2);
  s.inputs = Json::array();
  EXPECT_NO_THROW(check_search("novel_policy", s, true, "stages[1].search"));
  try {
    check_search("novel_policy", s, false, "stages[1].search");
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_EQ(std::string(e.what()),
              "stages[1].search.algorithm: \"novel_policy\" seeks novel policies for an earlier "
              "stage's trials, but the stage has no \"inputs\"");
  }
  s.config = {{"trials_per_input", 0}};
  EXPECT_THROW(check_search("novel_policy", s, true, "stages[1].search"), base::UserError);
  for (const auto& algorithm : algorithm_names()) {
    SearchSetup any = stage2(2);
    any.config = Json::object();
    EXPECT_NO_THROW(check_search(algorithm, any, true, "stages[1].search")) << algorithm;
  }
}

}  // namespace
}  // namespace podium::search
