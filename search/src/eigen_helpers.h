#pragma once
// Eigen helpers shared by the model-based algorithms: vectors to and from JSON arrays (saved
// states), and points of the unit cube mapped into a parameter space.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "podium/base/json.h"
#include "podium/search/space.h"

namespace podium::search {

inline base::Json vector_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

inline Eigen::VectorXd vector_from(const base::Json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

/// u in [0,1]^d to parameters: scaled into each bound, clamped, integers rounded inside the bounds.
inline std::vector<double> unit_to_params(const Space& space, const Eigen::VectorXd& u) {
  std::vector<double> x(space.dim());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto& p = space.params[i];
    x[i] = std::clamp(p.low + u[static_cast<Eigen::Index>(i)] * (p.high - p.low), p.low, p.high);
    if (p.integer) x[i] = std::clamp(std::round(x[i]), std::ceil(p.low), std::floor(p.high));
  }
  return x;
}

}  // namespace podium::search
