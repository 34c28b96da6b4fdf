#include "podium/search/strategies.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "podium/base/error.h"

namespace podium::search {

double feature_distance(const std::vector<Feature>& features, const std::vector<double>& a,
                        const std::vector<double>& b) {
  PODIUM_CHECK(a.size() == features.size() && b.size() == features.size(), "feature_distance: size mismatch");
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    double d = std::abs(a[i] - b[i]);
    if (features[i].metric == FeatureMetric::angular) {
      d = std::fmod(d, 2.0 * std::numbers::pi);
      d = std::min(d, 2.0 * std::numbers::pi - d);
    }
    sum += d * d;
  }
  return std::sqrt(sum);
}

std::vector<int> group_strategies(const std::vector<Feature>& features,
                                  const std::vector<std::vector<double>>& vectors, double threshold) {
  if (!(threshold >= 0.0))
    throw base::UserError("strategies: distance threshold " + std::to_string(threshold) + " is not >= 0");
  std::vector<int> group(vectors.size());
  std::vector<std::size_t> leaders;
  for (std::size_t v = 0; v < vectors.size(); ++v) {
    if (vectors[v].size() != features.size())
      throw base::UserError("strategies: feature vector " + std::to_string(v) + " has " +
                            std::to_string(vectors[v].size()) + " values but " + std::to_string(features.size()) +
                            " features are declared");
    auto it = std::find_if(leaders.begin(), leaders.end(), [&](std::size_t leader) {
      return feature_distance(features, vectors[leader], vectors[v]) <= threshold;
    });
    if (it == leaders.end()) {
      group[v] = static_cast<int>(leaders.size());
      leaders.push_back(v);
    } else {
      group[v] = static_cast<int>(it - leaders.begin());
    }
  }
  return group;
}

int count_strategies(const std::vector<Feature>& features, const std::vector<std::vector<double>>& vectors,
                     double threshold) {
  const auto group = group_strategies(features, vectors, threshold);
  return group.empty() ? 0 : 1 + *std::max_element(group.begin(), group.end());
}

}  // namespace podium::search
