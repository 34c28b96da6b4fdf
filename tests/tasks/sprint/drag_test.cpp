// Wind drag split by frontal area (sprint seed §2 "Initial State"): the formula on hand-made
// velocities, and the forces sim applies to humanoid34 at a known velocity.
#include "drag.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>

#include "podium/base/error.h"

namespace podium::tasks::sprint {
namespace {

TEST(SprintDrag, ForceIsTheQuadraticDragFormula) {
  const Eigen::Vector3d v(5.0, 0.3, -0.2), w(-2.0, 0.0, 0.0);
  const Eigen::Vector3d rel(7.0, 0.3, -0.2);
  const Eigen::Vector3d f = drag_force(v, w, 0.25, 1.2);
  EXPECT_LE((f - (-0.5 * 1.2 * 0.25 * std::sqrt(49.0 + 0.09 + 0.04) * rel)).norm(), 1e-14);
  EXPECT_LT(f.dot(rel), 0.0);  // against the relative motion
  EXPECT_EQ(drag_force(Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(2, 0, 0), 0.25, 1.2),
            Eigen::Vector3d::Zero());  // running with the wind
}

TEST(SprintDrag, WholeBodyAreaIsSplitByFrontalArea) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const SprintDrag drag(model);
  const auto& cda = drag.body_cda();
  ASSERT_EQ(cda.size(), model->bodies().size());
  EXPECT_NEAR(std::accumulate(cda.begin(), cda.end(), 0.0), 0.25, 1e-15);
  const double area = std::accumulate(drag.frontal_areas().begin(), drag.frontal_areas().end(), 0.0);
  for (std::size_t b = 0; b < cda.size(); ++b) {
    EXPECT_GT(drag.frontal_areas()[b], 0.0) << model->bodies()[b].name;
    EXPECT_NEAR(cda[b], 0.25 * drag.frontal_areas()[b] / area, 1e-15);
  }
  // The pelvis sphere's disc, πr² (r = 0.1057 m): the projection is sim's.
  EXPECT_NEAR(drag.frontal_areas()[0], std::numbers::pi * 0.1057 * 0.1057, 1e-12);
  std::printf("humanoid34 frontal area %.3f m² (standing); C_dA 0.25 m² ⇒ C_d %.2f\n", area, 0.25 / area);
  EXPECT_THROW(SprintDrag(model, DragConfig{1.2, -0.1}), base::UserError);
}

// Running at 5 m/s into a 2 m/s headwind and with a 2 m/s tailwind: every body's external force
// is −½ρ(C_dA)_b|v − w|(v − w); the whole body's is −½·1.2·0.25·|Δ|Δ. With the body also turning,
// each body's own centroid velocity goes into its force.
TEST(SprintDrag, AppliedForceEqualsTheFormulaOnABodyAtKnownVelocity) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const SprintDrag drag(model);
  sim::World world(model, sim::WorldConfig{});
  const Eigen::VectorXd q = model->standing_pose(), joints = Eigen::VectorXd::Zero(model->nv() - 6);
  const int bodies = static_cast<int>(model->bodies().size());
  for (const double wind : {-2.0, 2.0}) {
    world.set_state_world(q, Eigen::Vector3d::Zero(), Eigen::Vector3d(5, 0, 0), joints);
    drag.apply(world, Eigen::Vector3d(wind, 0, 0));
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (int b = 0; b < bodies; ++b) total += world.external_force(b);
    const double rel = 5.0 - wind;
    EXPECT_NEAR(total.x(), -0.5 * 1.2 * 0.25 * rel * rel, 1e-12) << "wind " << wind;
    EXPECT_NEAR(total.tail<2>().norm(), 0.0, 1e-12);
    std::printf("wind %+.0f m/s at 5 m/s: drag %.4f N\n", wind, total.x());
  }
  world.set_state_world(q, Eigen::Vector3d(0.3, -1.0, 2.0), Eigen::Vector3d(5, 0.5, 0.1), joints);
  drag.apply(world, Eigen::Vector3d(-1.5, 0, 0));
  for (int b = 0; b < bodies; ++b) {
    const Eigen::Vector3d v = world.body_centroid_velocity(b), rel = v - Eigen::Vector3d(-1.5, 0, 0);
    const Eigen::Vector3d expected = -0.5 * 1.2 * drag.body_cda()[b] * rel.norm() * rel;
    EXPECT_LE((world.external_force(b) - expected).norm(), 1e-12) << model->bodies()[b].name;
  }
}

}  // namespace
}  // namespace podium::tasks::sprint
