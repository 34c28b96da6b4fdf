#pragma once
/// Wind drag on the sprinter (sprint seed §2 "Initial State": wind speed is randomised per
/// episode; the seed gives no drag model). Each body i feels F_i = −½ ρ (C_dA)_i |v_i − w| (v_i − w),
/// v_i its centroid's velocity, w the wind; the whole-body drag area C_dA (0.25 m², a sprinter's
/// usual figure) is split over the bodies by their frontal area (projected on the plane normal to
/// the track, +x, in the model's standing pose, by sim's projected-area rule: sim::World::wind_force).
/// Applied through sim's external forces (World::set_external_force), refreshed every control step.
#include <Eigen/Core>
#include <vector>

#include "podium/sim/world.h"

namespace podium::tasks::sprint {

struct DragConfig {
  double air_density = 1.2;  ///< ρ, kg/m³
  double cda_m2 = 0.25;      ///< whole-body C_d·A, m²
};

/// F = −½ ρ C_dA |v − w| (v − w), N.
Eigen::Vector3d drag_force(const Eigen::Vector3d& velocity, const Eigen::Vector3d& wind, double cda_m2, double air_density);

class SprintDrag {
 public:
  /// Splits config.cda_m2 over the model's bodies by frontal area. Throws base::UserError for
  /// ρ < 0, C_dA < 0 or a model without frontal area.
  SprintDrag(const sim::ModelPtr& model, DragConfig config = {});
  /// Per body: its frontal area in the standing pose, m², and its share of C_dA, m².
  const std::vector<double>& frontal_areas() const { return areas_; }
  const std::vector<double>& body_cda() const { return cda_; }
  /// Sets every body's external force to its drag at the World's current velocities (call after
  /// each control step; the force holds through the next one's simulation steps).
  void apply(sim::World& world, const Eigen::Vector3d& wind) const;

 private:
  DragConfig config_;
  std::vector<double> areas_, cda_;
};

}  // namespace podium::tasks::sprint
