#include "jump_suite.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podium/base/error.h"

namespace podium::tasks::jump {

namespace {

void require_positive(double v, const char* name) {
  if (!(v > 0)) throw base::UserError(std::string("jump suite: ") + name + " " + std::to_string(v) + " is not > 0");
}

// A box whose near face lies `from_m` along n, `depth_m` deep along n, `length_m` across it,
// from the ground to `height_m`.
sim::BoxProp slab(const char* name, const Eigen::Vector3d& n, const Eigen::Quaterniond& frame, double from_m, double depth_m,
                  double length_m, double height_m, double friction) {
  sim::BoxProp b;
  b.name = name;
  b.center = (from_m + 0.5 * depth_m) * n + Eigen::Vector3d(0, 0, 0.5 * height_m);
  b.half_extents = Eigen::Vector3d(0.5 * depth_m, 0.5 * length_m, 0.5 * height_m);
  b.rotation = frame;
  b.friction = friction;
  return b;
}

}  // namespace

JumpSuite make_suite(JumpKind kind, double z_m, const SuiteLayout& l) {
  require_positive(z_m, kind == JumpKind::high_jump ? "bar height z" : "obstacle width z");
  for (auto [v, name] : {std::pair{l.wall_thickness_m, "wall_thickness_m"},
                         {l.wall_length_m, "wall_length_m"},
                         {l.obstacle_height_m, "obstacle_height_m"},
                         {l.obstacle_length_m, "obstacle_length_m"},
                         {l.block_depth_m, "block_depth_m"},
                         {l.block_length_m, "block_length_m"}})
    require_positive(v, name);
  // The obstacle jump runs straight at its box; only the high jump turns its suite (§3.6.1).
  const double alpha = kind == JumpKind::high_jump ? l.approach_angle_rad : std::numbers::pi / 2;
  JumpSuite s;
  s.plane_normal = Eigen::Vector3d(std::sin(alpha), std::cos(alpha), 0.0);
  s.bar_frame =
      Eigen::Quaterniond(Eigen::AngleAxisd(std::atan2(s.plane_normal.y(), s.plane_normal.x()), Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d& n = s.plane_normal;
  double near, depth, length, height;
  if (kind == JumpKind::high_jump) {
    near = l.wall_distance_m, depth = l.wall_thickness_m, length = l.wall_length_m, height = z_m;
  } else {
    near = l.obstacle_distance_m, depth = z_m, length = l.obstacle_length_m, height = l.obstacle_height_m;
  }
  // The authors' repository: wall friction 0.9, block 0.4.
  s.terrain.boxes.push_back(
      slab(kind == JumpKind::high_jump ? "bar" : "obstacle", n, s.bar_frame, near, depth, length, height, 0.9));
  s.block_top_m = std::clamp(height - 0.7, 0.02, 0.75);
  s.terrain.boxes.push_back(
      slab("block", n, s.bar_frame, near + depth + l.block_gap_m, l.block_depth_m, l.block_length_m, s.block_top_m, 0.4));
  // What a replay draws: the wall stands in for a crossbar at its top edge; the block is the mat.
  s.terrain.boxes[0].kind = kind == JumpKind::high_jump ? "crossbar" : "obstacle";
  s.terrain.boxes[1].kind = "mat";
  s.plane_point = (near + 0.5 * depth) * n;
  return s;
}

}  // namespace podium::tasks::jump
