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
  auto search = make_search("cmaes", box(5, Json::object()));
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
