#pragma once
/// Terrain and props. The ground is the plane z = 0, except inside terrain *regions* (flat
/// patches at a height, rough tiles with seeded heights of either sign, slopes), which replace it
/// by solid boxes; *props* are static boxes in any orientation (a bar, a crash mat, inclined
/// starting blocks). Height queries are analytic over all of it, so observers (the 5×5 height
/// map) need no physics engine. A World can take a new TerrainConfig between episodes.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace podium::sim {

/// A static box in world coordinates.
struct BoxProp {
  std::string name;                                              // for contacts and the replay
  Eigen::Vector3d center = Eigen::Vector3d::Zero();              // m
  Eigen::Vector3d half_extents{0.5, 0.5, 0.5};                   // m, along the box's own axes
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // box axes in world
  double friction = 1.0;                                         // multiplies the character's μ
  /// What the box stands for, for a replay (web_dashboard/README.md "Trajectory files"): "" a box;
  /// "crossbar" (the box is a bar's collision stand-in, the bar at its top edge), "obstacle", "mat".
  std::string kind;
};

/// An axis-aligned rectangle of ground, [min, max] in x and y, whose surface replaces the plane.
struct TerrainRegion {
  enum class Kind {
    flat,   ///< height `height_m` everywhere
    rough,  ///< square tiles of `tile_size_m`, heights uniform in [min_tile_height_m, max_tile_height_m]
    slope,  ///< rises at `slope_rad` along +x from `height_m` at x = min.x (an inclined box)
  };
  Kind kind = Kind::flat;
  Eigen::Vector2d min{-10.0, -10.0}, max{10.0, 10.0};  // m
  double height_m = 0.0;
  double tile_size_m = 1.0;
  double min_tile_height_m = 0.0, max_tile_height_m = 0.0;  // may be negative (pits)
  std::uint64_t seed = 0;                                   // tile heights
  double slope_rad = 0.0;                                   // in (−π/2, π/2)
};

struct TerrainConfig {
  std::vector<TerrainRegion> regions;  // must not overlap
  std::vector<BoxProp> boxes;          // props

  /// One rough region of 20 × 20 one-metre tiles at the curves get-up paper's levels: "easy"
  /// (≤ 5 cm), "medium" (≤ 10 cm), "hard" (≤ 20 cm). Throws base::UserError for another name.
  static TerrainConfig rough(const std::string& level, std::uint64_t seed);
};

/// What a region is built of: solid boxes (world coordinates), also what the replay draws.
struct TerrainPiece {
  int region = 0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), half_extents = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

class Terrain {
 public:
  /// Validates the config (sizes > 0, regions inside-out or overlapping, |slope| < π/2);
  /// throws base::UserError naming the region or prop.
  explicit Terrain(TerrainConfig config);
  const TerrainConfig& config() const { return config_; }
  /// Surface height (m) below (x, y): the top of the highest prop there, else the region's
  /// surface, else 0.
  double height(double x, double y) const;
  /// Heights on a 5×5 grid centred at (x, y), rotated by `yaw_rad`, spacing `spacing_m`,
  /// relative to `reference_z`, row-major from (−2, −2) to (2, 2) in the rotated frame.
  std::array<double, 25> height_map(double x, double y, double yaw_rad, double spacing_m, double reference_z) const;
  /// Index of the region containing (x, y), or −1 (the plane z = 0 is there).
  int region_at(double x, double y) const;
  /// The boxes the regions are made of (tiles reach kPieceDepthM below their top or 0, whichever is lower).
  const std::vector<TerrainPiece>& pieces() const { return pieces_; }
  /// Height of tile (i, j) of region r (i along x).
  double tile_height(int r, int i, int j) const;
  static constexpr double kPieceDepthM = 0.5;

 private:
  TerrainConfig config_;
  std::vector<std::vector<double>> tiles_;  // per region: tile heights, i-major
  std::vector<std::array<int, 2>> tile_counts_;
  std::vector<TerrainPiece> pieces_;
};

}  // namespace podium::sim
