// World's external forces: per-body forces at the body centroids and wind drag.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "internal.h"
#include "podium/base/error.h"
#include "podium/sim/world.h"

namespace podium::sim {

void World::set_external_force(int body, const Eigen::Vector3d& force_world) {
  if (body < 0 || body >= static_cast<int>(forces_.size()))
    throw base::UserError("sim: external force on body " + std::to_string(body) + ": model " + model_->name() + " has " +
                          std::to_string(forces_.size()) + " bodies");
  forces_[body] = force_world;
  has_forces_ = std::any_of(forces_.begin(), forces_.end(), [](const Eigen::Vector3d& f) { return !f.isZero(0.0); });
}

Eigen::Vector3d World::body_centroid(int body) const {
  const LinkData& d = data_.links[model_->bodies().at(body).link];
  return d.p + d.R * centroids_[body];
}

Eigen::Vector3d World::body_centroid_velocity(int body) {
  internal::velocity_pass(*model_, data_);
  const LinkData& d = data_.links[model_->bodies().at(body).link];
  return d.R * (d.v.tail<3>() + d.v.head<3>().cross(centroids_[body]));
}

// F = ½ ρ C_d A |v_rel| v_rel; A projects each geom on the plane normal to u = v_rel/|v_rel|:
// a sphere πr², a capsule 2r·2h·|u × axis| + πr², a box Σ_k (face area ⊥ axis k)·|u · axis k|.
Eigen::Vector3d World::wind_force(int body, const Wind& wind) {
  const Eigen::Vector3d v_rel = wind.velocity - body_centroid_velocity(body);
  const double speed = v_rel.norm();
  if (speed == 0.0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d u = v_rel / speed;
  const Link& l = model_->links()[model_->bodies()[body].link];
  const Eigen::Matrix3d& R = data_.links[model_->bodies()[body].link].R;
  double area = 0.0;
  for (const Geom& g : l.geoms) {
    if (g.body != body) continue;
    const Eigen::Matrix3d Rg = R * g.rot.toRotationMatrix();
    const double disc = std::numbers::pi * g.radius * g.radius;
    switch (g.type) {
      case ShapeType::sphere:
        area += disc;
        break;
      case ShapeType::capsule:
        area += 4.0 * g.radius * g.half_length * u.cross(Rg.col(2)).norm() + disc;
        break;
      case ShapeType::box: {
        const Eigen::Vector3d& e = g.half_extents;
        const Eigen::Vector3d faces(4 * e.y() * e.z(), 4 * e.x() * e.z(), 4 * e.x() * e.y());
        for (int k = 0; k < 3; ++k) area += faces(k) * std::abs(u.dot(Rg.col(k)));
        break;
      }
    }
  }
  return 0.5 * wind.air_density * wind.drag_coefficient * area * speed * v_rel;
}

void World::apply_wind(const Wind& wind) {
  for (int b = 0; b < static_cast<int>(forces_.size()); ++b) set_external_force(b, wind_force(b, wind));
}

}  // namespace podium::sim
