// HeadWatch on hand-made head-top heights: a get-up that stands against a leap loop.
#include "head_watch.h"

#include <gtest/gtest.h>

#include <vector>

namespace podium::tasks::getup {
namespace {

HeadWatch watch(const std::vector<double>& heads) {
  HeadWatch w{.height_m = 1.2};
  for (std::size_t i = 0; i < heads.size(); ++i) w.observe(static_cast<int>(i), heads[i]);
  return w;
}

TEST(HeadWatch, StandingPassesOnceAndLeapingDropsEachTime) {
  const HeadWatch lying = watch({0.2, 0.3, 0.25});
  EXPECT_FALSE(lying.risen());
  EXPECT_EQ(lying.drops, 0);
  EXPECT_EQ(lying.peak_m, 0.3);

  const HeadWatch stands = watch({0.2, 0.8, 1.3, 1.56, 1.55, 1.56});
  EXPECT_EQ(stands.first_step, 2);
  EXPECT_EQ(stands.drops, 0);
  EXPECT_EQ(stands.peak_m, 1.56);

  // Up, airborne, down to the ground, up again, ending in the air: two drops, not one success.
  const HeadWatch leaps = watch({0.2, 1.5, 1.9, 1.0, 0.2, 1.4, 1.85, 0.3, 1.3});
  EXPECT_EQ(leaps.first_step, 1);
  EXPECT_EQ(leaps.drops, 2);
  EXPECT_EQ(leaps.peak_m, 1.9);
  EXPECT_TRUE(leaps.above());
  // Up at the end, but only for its last step: it did not stand; the standing one held 4 steps.
  EXPECT_EQ(leaps.held, 1);
  EXPECT_FALSE(leaps.stood(2));
  EXPECT_EQ(stands.held, 4);
  EXPECT_TRUE(stands.stood(4));
  EXPECT_FALSE(stands.stood(5));

  // Exactly at the height is not above it (success is head > height).
  EXPECT_FALSE(watch({1.2, 1.2}).risen());

  // The summary averages over the episodes that rose only, and counts those that stood.
  const HeadSummary s = summarise_heads({lying, stands, leaps}, 3);
  EXPECT_EQ(s.risen, 2);
  EXPECT_EQ(s.stood, 1);
  EXPECT_EQ(summarise_heads({lying, stands, leaps}, 1).stood, 2);
  EXPECT_DOUBLE_EQ(s.first_step, 1.5);
  EXPECT_DOUBLE_EQ(s.drops, 1.0);
  EXPECT_DOUBLE_EQ(s.peak_m, (1.56 + 1.9) / 2);
  EXPECT_EQ(summarise_heads({lying}, 0).peak_m, 0.0);
  EXPECT_EQ(summarise_heads({lying}, 0).stood, 0);
}

// The episodes that began on the back, apart: counted, and of them the risen and the stood.
TEST(HeadWatch, BackSummaryCountsOnlyTheEpisodesOnTheBack) {
  const HeadWatch lying = watch({0.2, 0.3, 0.25});
  const HeadWatch stands = watch({0.2, 0.8, 1.3, 1.56, 1.55, 1.56});
  const HeadWatch leaps = watch({0.2, 1.5, 1.9, 1.0, 0.2, 1.4, 1.85, 0.3, 1.3});
  const BackSummary b = summarise_back({lying, stands, leaps, stands}, {1, 1, 1, 0}, 3);
  EXPECT_EQ(b.falls, 3);
  EXPECT_EQ(b.risen, 2);
  EXPECT_EQ(b.stood, 1);  // the fourth stood, but from the front
  const BackSummary none = summarise_back({stands}, {0}, 3);
  EXPECT_EQ(none.falls, 0);
  EXPECT_EQ(none.risen, 0);
}

// The replay shows the first episode that stood, else the first that rose, else the first.
TEST(HeadWatch, ShownEpisodeIsTheFirstThatStoodElseRose) {
  const HeadWatch lying = watch({0.2, 0.3, 0.25});
  const HeadWatch stands = watch({0.2, 0.8, 1.3, 1.56, 1.55, 1.56});
  const HeadWatch leaps = watch({0.2, 1.5, 1.9, 1.0, 0.2, 1.4, 1.85, 0.3, 1.3});
  EXPECT_EQ(shown_episode({lying, leaps, stands, stands}, 3), 2u);
  EXPECT_EQ(shown_episode({lying, leaps, stands}, 5), 1u);  // none held 5 steps: the first that rose
  EXPECT_EQ(shown_episode({lying, lying}, 3), 0u);
  EXPECT_EQ(shown_episode({}, 3), 0u);
}

}  // namespace
}  // namespace podium::tasks::getup
