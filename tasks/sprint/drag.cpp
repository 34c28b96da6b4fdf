// Wind drag split by frontal area (sprint seed §2 "Initial State": wind randomised per episode).
#include "drag.h"

#include <numeric>
#include <string>

#include "podium/base/error.h"

namespace podium::tasks::sprint {

Eigen::Vector3d drag_force(const Eigen::Vector3d& velocity, const Eigen::Vector3d& wind, double cda_m2, double air_density) {
  const Eigen::Vector3d rel = velocity - wind;
  return -0.5 * air_density * cda_m2 * rel.norm() * rel;
}

SprintDrag::SprintDrag(const sim::ModelPtr& model, DragConfig config) : config_(config) {
  if (!(config.air_density >= 0.0) || !(config.cda_m2 >= 0.0))
    throw base::UserError("sprint: drag air_density " + std::to_string(config.air_density) + " and cda_m2 " +
                          std::to_string(config.cda_m2) + " must be ≥ 0");
  // sim's projected-area rule: at rest in a unit wind along +x with ½ρC_d = 1, a body's drag is
  // its frontal area (in newtons, numerically).
  sim::WorldConfig wc;
  wc.gravity.setZero();
  sim::World world(model, wc);
  world.reset(model->standing_pose(), Eigen::VectorXd::Zero(model->nv()));
  sim::Wind probe;
  probe.velocity = Eigen::Vector3d::UnitX();
  probe.air_density = 2.0;
  probe.drag_coefficient = 1.0;
  const int bodies = static_cast<int>(model->bodies().size());
  for (int b = 0; b < bodies; ++b) areas_.push_back(world.wind_force(b, probe).x());
  const double total = std::accumulate(areas_.begin(), areas_.end(), 0.0);
  if (!(total > 0.0)) throw base::UserError("sprint: model " + model->name() + " has no frontal area to split the drag over");
  for (const double a : areas_) cda_.push_back(config.cda_m2 * a / total);
}

void SprintDrag::apply(sim::World& world, const Eigen::Vector3d& wind) const {
  for (int b = 0; b < static_cast<int>(cda_.size()); ++b)
    world.set_external_force(b, drag_force(world.body_centroid_velocity(b), wind, cda_[b], config_.air_density));  // §2
}

}  // namespace podium::tasks::sprint
