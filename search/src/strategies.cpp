#include "podium/search/strategies.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "podium/base/error.h"
#include "podium/base/rng.h"

namespace podium::search {

namespace {
constexpr double kTurn = 2.0 * std::numbers::pi;

void check_threshold(double threshold) {
  if (!(threshold > 0.0) || !std::isfinite(threshold))
    throw base::UserError("strategies: distance threshold " + std::to_string(threshold) + " is not > 0");
}

std::int64_t cells_of(const Feature& f, double threshold) {
  const double span = f.metric == FeatureMetric::angular ? kTurn : f.high - f.low;
  return std::max<std::int64_t>(1, std::llround(span / threshold));
}

// The cell of value v on feature f's grid of n cells.
std::int64_t cell_of(const Feature& f, std::int64_t n, double v) {
  if (f.metric == FeatureMetric::angular) {
    double a = std::fmod(v - f.low, kTurn);
    if (a < 0.0) a += kTurn;
    return std::min(n - 1, static_cast<std::int64_t>(std::floor(a / (kTurn / static_cast<double>(n)))));
  }
  const double width = (f.high - f.low) / static_cast<double>(n);
  const double k = std::floor((v - f.low) / width);
  return static_cast<std::int64_t>(std::clamp(k, 0.0, static_cast<double>(n - 1)));
}
}  // namespace

double feature_distance(const std::vector<Feature>& features, const std::vector<double>& a, const std::vector<double>& b) {
  PODIUM_CHECK(a.size() == features.size() && b.size() == features.size(), "feature_distance: size mismatch");
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    double d = std::abs(a[i] - b[i]);
    if (features[i].metric == FeatureMetric::angular) {
      d = std::fmod(d, kTurn);
      d = std::min(d, kTurn - d);
    }
    sum += d * d;
  }
  return std::sqrt(sum);
}

std::vector<std::int64_t> strategy_cells_per_feature(const std::vector<Feature>& features, double threshold) {
  check_threshold(threshold);
  std::vector<std::int64_t> n;
  for (const auto& f : features) n.push_back(cells_of(f, threshold));
  return n;
}

std::int64_t strategy_id(const std::vector<Feature>& features, const std::vector<double>& vector, double threshold) {
  if (features.empty() && vector.empty()) return 0;  // a stage without features: one strategy (its threshold is 0)
  check_threshold(threshold);
  if (vector.size() != features.size())
    throw base::UserError("strategies: a feature vector has " + std::to_string(vector.size()) + " values but " +
                          std::to_string(features.size()) + " features are declared");
  std::int64_t id = 0;
  for (std::size_t j = 0; j < features.size(); ++j) {
    const std::int64_t n = cells_of(features[j], threshold);
    id = id * n + cell_of(features[j], n, vector[j]);
  }
  return id;
}

std::vector<std::int64_t> strategy_ids(const std::vector<Feature>& features, const std::vector<std::vector<double>>& vectors,
                                       double threshold) {
  if (!features.empty()) check_threshold(threshold);
  std::vector<std::int64_t> ids;
  ids.reserve(vectors.size());
  for (std::size_t v = 0; v < vectors.size(); ++v) {
    if (vectors[v].size() != features.size())
      throw base::UserError("strategies: feature vector " + std::to_string(v) + " has " + std::to_string(vectors[v].size()) +
                            " values but " + std::to_string(features.size()) + " features are declared");
    ids.push_back(strategy_id(features, vectors[v], threshold));
  }
  return ids;
}

int count_strategies(const std::vector<Feature>& features, const std::vector<std::vector<double>>& vectors, double threshold,
                     const std::vector<bool>* success) {
  PODIUM_CHECK(!success || success->size() == vectors.size(), "count_strategies: success flags and vectors differ in size");
  const auto ids = strategy_ids(features, vectors, threshold);
  std::set<std::int64_t> cells;
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (!success || (*success)[i]) cells.insert(ids[i]);
  return static_cast<int>(cells.size());
}

int strategy_ceiling(const std::vector<Feature>& features, double threshold, const std::vector<double>& low,
                     const std::vector<double>& high) {
  check_threshold(threshold);
  PODIUM_CHECK(low.size() == features.size() && high.size() == features.size(), "strategy_ceiling: size mismatch");
  double cells = 1.0;
  for (std::size_t j = 0; j < features.size(); ++j) {
    const Feature& f = features[j];
    const std::int64_t n = cells_of(f, threshold);
    if (f.metric == FeatureMetric::angular && high[j] - low[j] >= kTurn) {
      cells *= static_cast<double>(n);
      continue;
    }
    // Cells met walking from low to high (an angular range may wrap past the grid's seam).
    const std::int64_t a = cell_of(f, n, low[j]), b = cell_of(f, n, high[j]);
    const std::int64_t met = b >= a ? b - a + 1 : (f.metric == FeatureMetric::angular ? n - a + b + 1 : 1);
    cells *= static_cast<double>(std::min(n, met));
  }
  return static_cast<int>(std::min(cells, 1e9));
}

double expected_random_count(const std::vector<Feature>& features, double threshold, const Space& space, const Outcome& outcome,
                             int samples, int draws, std::uint64_t seed) {
  PODIUM_CHECK(draws > 0 && samples >= 0, "expected_random_count: draws must be > 0");
  base::Rng rng(seed);
  double total = 0.0;
  for (int d = 0; d < draws; ++d) {
    std::set<std::int64_t> cells;
    for (int s = 0; s < samples; ++s) {
      std::vector<double> x;
      for (const auto& p : space.params) x.push_back(rng.uniform(p.low, p.high));
      if (const auto f = outcome(x)) cells.insert(strategy_id(features, *f, threshold));
    }
    total += static_cast<double>(cells.size());
  }
  return total / static_cast<double>(draws);
}

bool trial_success(const base::Json& rule, const base::Json& info) {
  if (rule.is_null()) return true;
  if (!rule.is_object() || !rule.contains("info") || !rule["info"].is_string())
    throw base::UserError("description.success: expected {\"info\": JSON pointer, \"min\"?: number}, got " + rule.dump());
  const std::string pointer = rule["info"].get<std::string>();
  base::Json::json_pointer p;
  try {
    p = base::Json::json_pointer(pointer);
  } catch (const std::exception&) {
    throw base::UserError("description.success.info: \"" + pointer + "\" is not a JSON pointer (e.g. \"/cleared\")");
  }
  if (!info.is_object() || !info.contains(p)) return false;  // the task did not say it succeeded
  const base::Json& v = info.at(p);
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number()) return v.get<double>() >= rule.value("min", 0.5);
  return false;
}

}  // namespace podium::search
