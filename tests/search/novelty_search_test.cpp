#include <gtest/gtest.h>

#include "podium/search/search.h"

namespace podium::search {
namespace {

TEST(NoveltySearch, ArchiveTakesOnlyFeaturesSparserThanTheThreshold) {
  SearchSetup s;
  s.space = Space::from_json(Json::parse(R"([{"name": "a", "low": 0, "high": 1}])"), "space");
  s.features = Feature::list_from_json(Json::parse(R"([{"name": "f", "low": 0, "high": 10}])"), "features");
  s.config = {{"k", 2}, {"archive_threshold", 1.0}, {"initial_samples", 2}};
  auto search = make_search("novelty", s);
  // Repeats of 3.0 are not novel; 5.0 and 5.4 are (ρ > 1); 5.2 between them is not.
  for (double f : {3.0, 3.0, 3.0, 5.0, 5.4, 5.2}) {
    const auto p = search->ask(1).at(0);
    EXPECT_GE(p.x[0], 0.0);
    EXPECT_LE(p.x[0], 1.0);
    search->tell({{p.id, true, {}, {f}}});
  }
  // Archive indices (tell order): 3.0 (first), 5.0 (ρ = 2), 5.4 (ρ = mean(0.4, 2.4) = 1.4); 5.2 has ρ = 0.2.
  EXPECT_EQ(search->save().at("archive"), Json::parse("[0, 3, 4]"));
  EXPECT_EQ(search->ask(1).at(0).info.at("step"), "mutate");
}

}  // namespace
}  // namespace podium::search
