#pragma once
/// The jump suite: the props of a jump as sim::BoxProps, placed relative to the take-off point
/// (the origin; the take-off state faces +x there). Thesis §3.6.1: the crossbar is "a rigid wall
/// vertically extending from the ground to the target height" during training; the obstacle is a
/// 50 cm high box of width z; the crash mat is a rigid block behind either.
///
/// The suite turns about the take-off point by the approach angle α (§3.6.1: "we simply rotate the
/// high jump suite"): the wall's normal, pointing from the take-off side over the bar, is
/// n(α) = (sin α, cos α, 0). α = 0 puts the bar parallel to the run, on the left (the thesis's
/// wall line x sin α − z cos α = 0 in its y-up frame, whose −z is our +y: Table 3.3's Fosbury flop
/// has α ≈ 0 after a curve to the left); α = π/2 puts it straight across the run.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>

#include "jump_schedules.h"
#include "podium/sim/terrain.h"

namespace podium::tasks::jump {

/// Dimensions the thesis leaves open; the defaults follow the authors' repository (arpspoof/Jump:
/// wall 1.2 m from the take-off point, 5 cm thick, 20 m long; block 2 cm behind it, 4 m deep,
/// top at clip(h − 0.7, 0.02, 0.75) for a bar (obstacle) height h).
struct SuiteLayout {
  double approach_angle_rad = std::numbers::pi / 2;  ///< α (high jump only); π/2: the bar across the run
  double wall_distance_m = 1.2;                      ///< take-off point to the wall's near face, along n
  double wall_thickness_m = 0.05;
  double wall_length_m = 20.0;
  double obstacle_distance_m = 1.0;  ///< take-off point to the obstacle's near face
  double obstacle_height_m = 0.5;    ///< §3.6.1
  double obstacle_length_m = 6.0;    ///< across the run
  double block_gap_m = 0.02;         ///< wall (obstacle) far face to the block
  double block_depth_m = 4.0;        ///< along n
  double block_length_m = 6.0;       ///< across n
};

struct JumpSuite {
  sim::TerrainConfig terrain;  ///< boxes: [obstacle (the wall or the box), block]
  int obstacle_prop = 0;       ///< index of the wall / obstacle box in terrain.boxes
  int block_prop = 1;          ///< index of the landing block
  /// The vertical plane the strategy feature is read at (§3.6.1): the wall's mid-plane, or the
  /// obstacle's centre plane; a point on it (on the ground) and its unit normal n.
  Eigen::Vector3d plane_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitX();
  /// The bar frame: x = n, z = up, y = z × x (along the bar), as a rotation from bar to world.
  Eigen::Quaterniond bar_frame = Eigen::Quaterniond::Identity();
  double block_top_m = 0.0;

  /// Signed distance (m) of a point to the plane, positive past it.
  double signed_distance(const Eigen::Vector3d& p) const { return plane_normal.dot(p - plane_point); }
};

/// The suite of difficulty z. Throws base::UserError for z ≤ 0 or a non-positive dimension.
JumpSuite make_suite(JumpKind kind, double z_m, const SuiteLayout& layout);

}  // namespace podium::tasks::jump
