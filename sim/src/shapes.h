#pragma once
// Volume and inertia of the primitive shapes (capsule, sphere, box) for mass properties.
#include <Eigen/Core>
#include <numbers>

#include "podium/sim/model.h"

namespace podium::sim {

inline double geom_volume(const Geom& g) {
  const double pi = std::numbers::pi;
  switch (g.type) {
    case ShapeType::sphere:
      return 4.0 / 3.0 * pi * g.radius * g.radius * g.radius;
    case ShapeType::capsule:
      return pi * g.radius * g.radius * (2.0 * g.half_length) + 4.0 / 3.0 * pi * g.radius * g.radius * g.radius;
    case ShapeType::box:
      return 8.0 * g.half_extents.prod();
  }
  return 0.0;
}

/// Inertia per unit mass about the centre, in the shape's own frame (capsule along z).
inline Eigen::Matrix3d geom_unit_inertia(const Geom& g) {
  const double r = g.radius;
  switch (g.type) {
    case ShapeType::sphere:
      return Eigen::Matrix3d::Identity() * (0.4 * r * r);
    case ShapeType::box: {
      const Eigen::Vector3d e = 2.0 * g.half_extents;
      return Eigen::Vector3d(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(), e.x() * e.x() + e.y() * e.y())
                 .asDiagonal() *
             (1.0 / 12.0);
    }
    case ShapeType::capsule: {
      // Cylinder of length h plus two hemispheres, mass split by volume.
      const double h = 2.0 * g.half_length;
      const double vc = r * r * h, vs = 4.0 / 3.0 * r * r * r;
      const double mc = vc / (vc + vs), ms = vs / (vc + vs);
      const double izz = mc * r * r / 2.0 + ms * 0.4 * r * r;
      const double ixx = mc * (r * r / 4.0 + h * h / 12.0) + ms * (0.4 * r * r + h * h / 4.0 + 3.0 * h * r / 8.0);
      return Eigen::Vector3d(ixx, ixx, izz).asDiagonal();
    }
  }
  return Eigen::Matrix3d::Zero();
}

}  // namespace podium::sim
