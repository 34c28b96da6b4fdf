// The step counter on scripted contact sequences (sprint seed §2 "State": z, the normalised
// number of alternating steps).
#include "steps.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "podium/base/error.h"

namespace podium::tasks::sprint {
namespace {

// Feeds "L", "R", "B" (both) or "-" (neither) observations; returns the steps after each.
std::vector<int> feed(StepCounter& counter, const std::string& script) {
  std::vector<int> steps;
  for (const char c : script) {
    counter.observe(c == 'L' || c == 'B', c == 'R' || c == 'B');
    steps.push_back(counter.steps());
  }
  return steps;
}

TEST(SprintSteps, RepeatedTouchdownsOfOneFootCountOnce) {
  StepCounter counter({.debounce = 2, .n_norm = 10.0});
  counter.reset(false, false);
  feed(counter, "--LLL---LLL--LL-");  // the left foot lands three times
  EXPECT_EQ(counter.steps(), 1);
  EXPECT_EQ(counter.last_foot(), Foot::left);
  feed(counter, "RRR");
  EXPECT_EQ(counter.steps(), 2);
  EXPECT_EQ(counter.last_foot(), Foot::right);
  feed(counter, "-RR-RR");  // the right again: still two
  EXPECT_EQ(counter.steps(), 2);
}

TEST(SprintSteps, ZRisesByOneOverNNormPerAlternatingStep) {
  const double n_norm = 7.0;
  StepCounter counter({.debounce = 2, .n_norm = n_norm});
  counter.reset(false, false);  // in flight
  EXPECT_EQ(counter.z(), 0.0);
  const std::string stride = "LLL--RRRR--";  // stance, flight, stance, flight
  double z = 0.0;
  for (int s = 0; s < 6; ++s) {
    const std::vector<int> steps = feed(counter, stride);
    // Each stance counts once, at its second observation in contact (debounce 2).
    EXPECT_EQ(steps[0], 2 * s);
    EXPECT_EQ(steps[1], 2 * s + 1);
    EXPECT_EQ(steps[5], 2 * s + 1);
    EXPECT_EQ(steps[6], 2 * s + 2);
    EXPECT_DOUBLE_EQ(counter.z() - z, 2.0 / n_norm);
    z = counter.z();
  }
  EXPECT_DOUBLE_EQ(counter.z(), 12.0 / n_norm);
}

TEST(SprintSteps, FeetDownAtTheStartAndFlickerAreNotSteps) {
  StepCounter counter({.debounce = 3, .n_norm = 10.0});
  counter.reset(true, false);  // left foot in contact at the start
  feed(counter, "LLLLLL");
  EXPECT_EQ(counter.steps(), 0);
  feed(counter, "-R-R-RR-");  // contacts shorter than the debounce
  EXPECT_EQ(counter.steps(), 0);
  feed(counter, "RRR");
  EXPECT_EQ(counter.steps(), 1);
  EXPECT_EQ(counter.last_foot(), Foot::right);
  feed(counter, "--LLL");  // the left, lifted once, now lands
  EXPECT_EQ(counter.steps(), 2);
}

TEST(SprintSteps, BothFeetLandingTogetherCountTheOppositeFootOnly) {
  StepCounter counter({.debounce = 1, .n_norm = 10.0});
  counter.reset(false, false);
  feed(counter, "-R-");
  feed(counter, "B");  // both land: the left is opposite to the last (right)
  EXPECT_EQ(counter.steps(), 2);
  EXPECT_EQ(counter.last_foot(), Foot::left);
}

TEST(SprintSteps, StateRoundTripsAndBadConfigIsRefused) {
  StepCounter a({.debounce = 2, .n_norm = 10.0});
  a.reset(false, false);
  feed(a, "-LL--R");  // mid-touchdown of the right foot
  StepCounter b({.debounce = 2, .n_norm = 10.0});
  b.load_state(a.state());
  EXPECT_EQ(feed(a, "R--LL"), feed(b, "R--LL"));
  EXPECT_EQ(a.state(), b.state());
  EXPECT_THROW(StepCounter({.debounce = 0, .n_norm = 1.0}), base::UserError);
  EXPECT_THROW(StepCounter({.debounce = 1, .n_norm = 0.0}), base::UserError);
  EXPECT_THROW(b.load_state(base::Json{{"steps", 1}}), base::UserError);
}

}  // namespace
}  // namespace podium::tasks::sprint
