#pragma once
/// Episode starts: standing, the get-up seed's ragdoll drop (§7), and random poses.
#include "podium/base/rng.h"
#include "podium/sim/world.h"

namespace podium::sim {

/// A random configuration: revolute joints uniform within their limits (±1 rad if unlimited),
/// spherical joints rotated up to `max_ball_angle_rad` about a random axis, root orientation
/// uniform, root at `root_height_m` (x = y = 0).
Eigen::VectorXd random_pose(const CharacterModel& model, base::Rng& rng, double root_height_m, double max_ball_angle_rad = 1.0);

/// Puts the character in its standing pose at rest.
void standing_start(World& world);

struct RagdollStart {
  double drop_height_m = 1.5;  ///< root height at release (seed §7: 1.5 m)
  int control_steps = 80;      ///< control steps of noisy actions (seed §7: 80)
  double action_sigma = 0.1;   ///< actions a ~ N(0, σ) in units of the torque limits (seed §7: 0.1)
};

/// get-up seed §7: release from `drop_height_m` in a random pose, apply torque actions
/// a ~ N(0, σ)·torque limits for `control_steps` control steps. Returns the last step's report.
/// The root is raised if needed so that no geom starts below 5 cm.
StepReport ragdoll_start(World& world, base::Rng& rng, const RagdollStart& options = {});

}  // namespace podium::sim
