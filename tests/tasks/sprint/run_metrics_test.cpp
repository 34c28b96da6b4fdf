// The Acceleration + Top Speed stage's measures on scripted sequences: the rise distance on lean
// sequences, the flight-phase check on contact sequences, the segment speeds on runs of known pace.
#include "run_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "podium/base/error.h"

namespace podium::tasks::sprint {
namespace {

constexpr double kDeg = M_PI / 180.0;

std::vector<double> positions(std::size_t n, double step_m) {
  std::vector<double> x;
  for (std::size_t i = 0; i < n; ++i) x.push_back(0.5 + step_m * static_cast<double>(i));
  return x;
}

TEST(SprintRiseDistance, IsWhereTheLeanDropsBelowTheThresholdForGood) {
  const std::vector<double> x = positions(8, 0.25);  // 0.5, 0.75, ..., 2.25 m
  // A steady rise: 45° lean easing to 10°; it first drops below 20° at the sixth sample.
  const std::vector<double> steady = {45 * kDeg, 40 * kDeg, 35 * kDeg, 28 * kDeg, 22 * kDeg, 18 * kDeg, 12 * kDeg, 10 * kDeg};
  ASSERT_TRUE(rise_distance(x, steady, 20 * kDeg));
  EXPECT_DOUBLE_EQ(*rise_distance(x, steady, 20 * kDeg), x[5]);
  // Dipping below and back over the threshold does not count: only the last drop is for good.
  const std::vector<double> relapse = {45 * kDeg, 15 * kDeg, 12 * kDeg, 25 * kDeg, 30 * kDeg, 19 * kDeg, 12 * kDeg, 10 * kDeg};
  EXPECT_DOUBLE_EQ(*rise_distance(x, relapse, 20 * kDeg), x[5]);
  // Exactly 20° is not below it.
  const std::vector<double> at = {45 * kDeg, 18 * kDeg, 20 * kDeg, 19 * kDeg, 10 * kDeg, 10 * kDeg, 10 * kDeg, 10 * kDeg};
  EXPECT_DOUBLE_EQ(*rise_distance(x, at, 20 * kDeg), x[3]);
  // Upright from the start: the rise is the first sample's x.
  EXPECT_DOUBLE_EQ(*rise_distance(x, std::vector<double>(8, 5 * kDeg), 20 * kDeg), x[0]);
  // Still leaning at the end: no rise.
  const std::vector<double> never = {45 * kDeg, 15 * kDeg, 12 * kDeg, 10 * kDeg, 10 * kDeg, 12 * kDeg, 18 * kDeg, 21 * kDeg};
  EXPECT_FALSE(rise_distance(x, never, 20 * kDeg));
  EXPECT_FALSE(rise_distance({}, {}, 20 * kDeg));
  EXPECT_THROW(rise_distance(x, {0.0}, 20 * kDeg), base::UserError);
}

// A run of strides from scripted phases: L stance, flight, R stance, flight, ... ; `flights` samples
// of flight between stances of `stance` samples (0 flights: one foot lands as the other lifts).
std::vector<FootContacts> strides(int count, int stance, int flights) {
  std::vector<FootContacts> c{{false, false}};
  for (int s = 0; s < count; ++s) {
    for (int k = 0; k < stance; ++k) c.push_back({s % 2 == 0, s % 2 == 1});
    for (int k = 0; k < flights; ++k) c.push_back({false, false});
  }
  return c;
}

TEST(SprintFlightPhase, EveryStrideInTheWindowNeedsBothFeetOff) {
  const std::vector<FootContacts> running = strides(8, 3, 1);
  const std::vector<double> x = positions(running.size(), 0.3);
  EXPECT_TRUE(flight_in_every_stride(x, running, 0.0));
  EXPECT_TRUE(flight_in_every_stride(x, running, x[x.size() / 2]));
  // Walking-like: the next foot lands as the last lifts, no sample with both off.
  const std::vector<FootContacts> grounded = strides(8, 3, 0);
  EXPECT_FALSE(flight_in_every_stride(positions(grounded.size(), 0.3), grounded, 0.0));
  // One stride without flight inside the window fails it; before the window it does not matter.
  std::vector<FootContacts> one = running;
  one[4] = {true, false};  // the first stride (touchdowns at samples 1 and 5): its flight sample 4 on the ground
  const std::vector<double> xo = positions(one.size(), 0.3);
  EXPECT_FALSE(flight_in_every_stride(xo, one, 0.0));
  EXPECT_TRUE(flight_in_every_stride(xo, one, xo[5]));
  // Double support (both feet down between the stances) is no flight either.
  std::vector<FootContacts> both = running;
  for (FootContacts& c : both)
    if (!c.left && !c.right) c = {true, true};
  both.front() = {false, false};
  EXPECT_FALSE(flight_in_every_stride(positions(both.size(), 0.3), both, 0.0));
  // No whole stride in the window: cannot tell, so false.
  EXPECT_FALSE(flight_in_every_stride(x, running, x.back()));
  EXPECT_THROW(flight_in_every_stride({0.0}, running, 0.0), base::UserError);
}

TEST(SprintSegmentSpeed, IsTheSegmentOverTheTimeBetweenItsCrossings) {
  // 2 m/s for 2 s, then 6 m/s: x = 2t, then 4 + 6(t − 2); samples at 30 Hz.
  std::vector<double> t, x;
  for (int i = 0; i <= 150; ++i) {
    const double s = i / 30.0;
    t.push_back(s), x.push_back(s <= 2.0 ? 2.0 * s : 4.0 + 6.0 * (s - 2.0));
  }
  EXPECT_NEAR(*segment_speed(t, x, 0.0, 3.0), 2.0, 1e-12);
  EXPECT_NEAR(*segment_speed(t, x, 10.0, 20.0), 6.0, 1e-12);
  // Across the change: 4 m at 2 m/s (2 s) and 6 m at 6 m/s (1 s).
  EXPECT_NEAR(*segment_speed(t, x, 0.0, 10.0), 10.0 / 3.0, 1e-12);
  // The run ends at 22 m (t = 5 s): to its end only when asked.
  EXPECT_FALSE(segment_speed(t, x, 20.0, 30.0));
  EXPECT_NEAR(*segment_speed(t, x, 16.0, 30.0, true), 6.0, 1e-12);
  EXPECT_FALSE(segment_speed(t, x, 40.0, 50.0, true));
}

}  // namespace
}  // namespace podium::tasks::sprint
