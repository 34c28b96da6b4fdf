#pragma once
/// Parameter spaces and feature declarations, read from a task's description (plain JSON, so the
/// plugin contract and the search layer need not include each other).
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::search {

/// One bounded parameter. Integer parameters are proposed as whole numbers.
struct Parameter {
  std::string name;
  double low = 0.0;
  double high = 1.0;
  bool integer = false;
};

/// A box of parameters.
struct Space {
  std::vector<Parameter> params;
  std::size_t dim() const { return params.size(); }
  bool contains(const std::vector<double>& x) const;
  /// Parses [{"name", "low", "high", "integer"?}, ...]; errors name `json_path`.
  static Space from_json(const base::Json& j, const std::string& json_path);
  base::Json to_json() const;
};

/// How distances between feature values are measured (angles wrap around).
enum class FeatureMetric { euclidean, angular };

/// One strategy-feature dimension, with the range its values are expected to lie in.
struct Feature {
  std::string name;
  double low = 0.0;
  double high = 1.0;
  FeatureMetric metric = FeatureMetric::euclidean;
  std::string unit;
  /// The feature takes a few exact values (levels, e.g. a plateau landscape) rather than a
  /// continuum; BDS's default diversity acquisition depends on it (bds.h). Description key
  /// "quantised" (default false).
  bool quantised = false;
  static std::vector<Feature> list_from_json(const base::Json& j, const std::string& json_path);
  static base::Json list_to_json(const std::vector<Feature>& features);
};

}  // namespace podium::search
