#pragma once
/// Episode starts: standing, the get-up seed's ragdoll drop (§7), and random poses.
#include <functional>

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
  /// Which way the torso faces at release; supine and prone land that way (tests/character).
  enum class Lying {
    any,     ///< the random pose's own uniform orientation
    supine,  ///< torso pitched so its front faces up (±0.2 rad of random tilt about x and y)
    prone,   ///< front down, likewise
  };
  double drop_height_m = 1.5;  ///< root height above the terrain at (x, y) at release (seed §7: 1.5 m)
  int control_steps = 80;      ///< control steps of noisy actions (seed §7: 80)
  double action_sigma = 0.1;   ///< actions a ~ N(0, σ) in units of the torque limits (seed §7: 0.1)
  Lying lying = Lying::any;
  double x_m = 0.0, y_m = 0.0;  ///< where the root is released
  double yaw_rad = 0.0;         ///< the whole pose turned by this about the vertical
  bool random_yaw = false;      ///< ... or by a uniform angle in [−π, π)
};

/// get-up seed §7: release from `drop_height_m` in a random pose (turned to lie as asked), apply
/// torque actions a ~ N(0, σ)·torque limits for `control_steps` control steps. Returns the
/// last step's report (stops at the first non-finite state). The root is raised if needed so
/// that no geom starts below 5 cm above the terrain under the root. `observer`, when given, is
/// called at the release (with null) and after each control step that leaves a finite state (with
/// the step's joint torques, nv values), to record the fall: the get-up seed repository stores its
/// steps as transitions.
using FallObserver = std::function<void(const Eigen::VectorXd* tau)>;
StepReport ragdoll_start(World& world, base::Rng& rng, const RagdollStart& options = {}, const FallObserver& observer = {});

}  // namespace podium::sim
