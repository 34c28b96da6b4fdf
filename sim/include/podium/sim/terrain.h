#pragma once
/// Terrain and props: flat ground, a slope, rough 1 m tiles with seeded random heights, static
/// boxes (crossbar-as-wall, obstacle, crash mat). Height queries are analytic, so observers
/// (the 5×5 height map) need no physics engine.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace podium::sim {

struct BoxProp {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();        // m
  Eigen::Vector3d half_extents{0.5, 0.5, 0.5};             // m
  double yaw_rad = 0.0;                                     // rotation about z
  double friction = 1.0;
};

struct TerrainConfig {
  enum class Kind { flat, slope, rough };
  Kind kind = Kind::flat;
  double slope_rad = 0.0;      // slope: ground rises along +x at this angle
  double tile_size_m = 1.0;    // rough: square tiles of this size
  int tiles_per_side = 20;     // rough: tiles cover [−n/2, n/2]² tiles around the origin
  double max_tile_height_m = 0.0;  // rough: heights uniform in [0, max]
  std::uint64_t seed = 0;          // rough: tile heights
  std::vector<BoxProp> boxes;

  /// Rough tiles at the curves get-up paper's levels: "easy" (≤ 5 cm), "medium" (≤ 10 cm),
  /// "hard" (≤ 20 cm). Throws base::UserError for another level name.
  static TerrainConfig rough(const std::string& level, std::uint64_t seed);
};

class Terrain {
 public:
  explicit Terrain(TerrainConfig config);
  const TerrainConfig& config() const { return config_; }
  /// Ground height (m) below (x, y), boxes included.
  double height(double x, double y) const;
  /// Heights on a 5×5 grid centred at (x, y), rotated by `yaw_rad`, spacing `spacing_m`,
  /// relative to `reference_z`, row-major from (−2, −2) to (2, 2) in the rotated frame.
  std::array<double, 25> height_map(double x, double y, double yaw_rad, double spacing_m, double reference_z) const;
  /// Height of tile (i, j), i, j in [0, tiles_per_side).
  double tile_height(int i, int j) const { return tiles_[i * config_.tiles_per_side + j]; }

 private:
  TerrainConfig config_;
  std::vector<double> tiles_;
};

}  // namespace podium::sim
