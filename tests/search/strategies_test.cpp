#include "podium/search/strategies.h"

#include <gtest/gtest.h>

#include <numbers>

#include "podium/base/error.h"

namespace podium::search {
namespace {

std::vector<Feature> features(const std::vector<FeatureMetric>& metrics) {
  std::vector<Feature> out;
  for (auto m : metrics) out.push_back(Feature{"f" + std::to_string(out.size()), -4.0, 4.0, m, ""});
  return out;
}

TEST(FeatureDistance, AngularWrapsAroundAndEuclideanDoesNot) {
  const auto f = features({FeatureMetric::angular, FeatureMetric::euclidean});
  const double pi = std::numbers::pi;
  EXPECT_NEAR(feature_distance(f, {-pi + 0.1, 0.0}, {pi - 0.1, 0.0}), 0.2, 1e-12);
  EXPECT_NEAR(feature_distance(f, {0.0, -pi + 0.1}, {0.0, pi - 0.1}), 2 * pi - 0.2, 1e-12);
  EXPECT_NEAR(feature_distance(f, {0.0, 0.0}, {3 * pi, 4.0}), std::hypot(pi, 4.0), 1e-12);  // 3π wraps to π
}

TEST(GroupStrategies, LeadersFoundStrategiesInOrder) {
  const auto f = features({FeatureMetric::euclidean});
  // 0.0 founds 0; 0.4 joins it; 0.6 is 0.6 from the leader (not 0.2 from 0.4): founds 1; 1.0 joins 1.
  EXPECT_EQ(group_strategies(f, {{0.0}, {0.4}, {0.6}, {1.0}, {-0.5}}, 0.5), (std::vector<int>{0, 0, 1, 1, 0}));
  EXPECT_EQ(count_strategies(f, {{0.0}, {0.4}, {0.6}, {1.0}, {-0.5}}, 0.5), 2);
  EXPECT_EQ(count_strategies(f, {}, 0.5), 0);
}

TEST(GroupStrategies, AngularFeaturesAcrossTheSeamAreOneStrategy) {
  const auto f = features({FeatureMetric::angular});
  const double pi = std::numbers::pi;
  EXPECT_EQ(count_strategies(f, {{pi - 0.05}, {-pi + 0.05}, {0.0}}, 0.2), 2);
}

TEST(GroupStrategies, RejectsWrongSizeNamingTheVector) {
  const auto f = features({FeatureMetric::euclidean, FeatureMetric::euclidean});
  try {
    group_strategies(f, {{0.0, 1.0}, {0.5}}, 0.1);
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("feature vector 1 has 1 values but 2 features"), std::string::npos) << e.what();
  }
  EXPECT_THROW(group_strategies(f, {}, -1.0), base::UserError);
}

}  // namespace
}  // namespace podium::search
