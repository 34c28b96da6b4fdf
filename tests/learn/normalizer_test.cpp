#include "podium/learn/normalizer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "podium/base/rng.h"

namespace podium::learn {
namespace {

TEST(RunningNormalizer, MatchesWholeSampleStatisticsWhateverTheBatching) {
  base::Rng rng(1);
  std::vector<double> data;
  for (int r = 0; r < 1000; ++r) {
    data.push_back(rng.normal(3.0, 2.0));
    data.push_back(rng.uniform(-10.0, 0.0));
  }
  RunningNormalizer whole(2), batched(2);
  whole.update(data, 1000);
  for (int r = 0; r < 1000;) {
    const int rows = std::min(1000 - r, 1 + r % 37);
    batched.update(std::span<const double>(data.data() + 2 * r, std::size_t(2 * rows)), std::size_t(rows));
    r += rows;
  }
  double mean0 = 0, var0 = 0;
  for (int r = 0; r < 1000; ++r) mean0 += data[2 * std::size_t(r)] / 1000;
  for (int r = 0; r < 1000; ++r) var0 += std::pow(data[2 * std::size_t(r)] - mean0, 2) / 1000;
  EXPECT_NEAR(whole.mean()[0], mean0, 1e-12);
  EXPECT_NEAR(whole.variance()[0], var0, 1e-10);
  for (int j = 0; j < 2; ++j) {
    EXPECT_NEAR(batched.mean()[std::size_t(j)], whole.mean()[std::size_t(j)], 1e-10);
    EXPECT_NEAR(batched.variance()[std::size_t(j)], whole.variance()[std::size_t(j)], 1e-9);
  }
}

TEST(RunningNormalizer, NormalizesAndClips) {
  RunningNormalizer n(1, 5.0);
  n.update(std::vector<double>{1.0, 3.0}, 2);  // mean 2, variance 1
  std::vector<float> out(1);
  n.normalize(std::vector<double>{4.0}, out);
  EXPECT_NEAR(out[0], 2.0, 1e-6);
  n.normalize(std::vector<double>{100.0}, out);
  EXPECT_FLOAT_EQ(out[0], 5.0f);
}

TEST(RunningNormalizer, SaveLoadRoundTripsExactly) {
  RunningNormalizer a(3), b(3);
  a.update(std::vector<double>{0.1, 0.2, 0.3, 1.0 / 3, 2.0 / 7, 5.5}, 2);
  b.load(a.save());
  EXPECT_EQ(a.mean(), b.mean());
  EXPECT_EQ(a.variance(), b.variance());
  EXPECT_EQ(a.count(), b.count());
  RunningNormalizer wrong(2);
  EXPECT_THROW(wrong.load(a.save()), std::exception);
}

}  // namespace
}  // namespace podium::learn
