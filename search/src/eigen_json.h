#pragma once
// Eigen vectors to and from JSON arrays, for the algorithms' saved states.
#include <Eigen/Dense>
#include <vector>

#include "podium/base/json.h"

namespace podium::search {

inline base::Json vector_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

inline Eigen::VectorXd vector_from(const base::Json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace podium::search
