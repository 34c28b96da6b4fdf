#include "podium/sim/terrain.h"

#include <algorithm>
#include <cmath>

#include "podium/base/error.h"
#include "podium/base/rng.h"

namespace podium::sim {

TerrainConfig TerrainConfig::rough(const std::string& level, std::uint64_t seed) {
  TerrainConfig c;
  c.kind = Kind::rough;
  c.seed = seed;
  if (level == "easy") c.max_tile_height_m = 0.05;
  else if (level == "medium") c.max_tile_height_m = 0.10;
  else if (level == "hard") c.max_tile_height_m = 0.20;
  else throw base::UserError("sim: terrain level \"" + level + "\" is not one of easy, medium, hard");
  return c;
}

Terrain::Terrain(TerrainConfig config) : config_(std::move(config)) {
  if (config_.kind == TerrainConfig::Kind::rough) {
    if (config_.tiles_per_side < 1 || !(config_.tile_size_m > 0))
      throw base::UserError("sim: rough terrain needs tiles_per_side ≥ 1 and tile_size_m > 0");
    base::Rng rng(config_.seed);
    tiles_.resize(static_cast<std::size_t>(config_.tiles_per_side) * config_.tiles_per_side);
    for (double& h : tiles_) h = rng.uniform(0.0, config_.max_tile_height_m);
  }
}

double Terrain::height(double x, double y) const {
  double h = 0.0;
  if (config_.kind == TerrainConfig::Kind::slope) h = x * std::tan(config_.slope_rad);
  if (config_.kind == TerrainConfig::Kind::rough) {
    const int n = config_.tiles_per_side;
    const int i = static_cast<int>(std::floor(x / config_.tile_size_m + n / 2.0));
    const int j = static_cast<int>(std::floor(y / config_.tile_size_m + n / 2.0));
    if (i >= 0 && i < n && j >= 0 && j < n) h = tile_height(i, j);
  }
  for (const BoxProp& b : config_.boxes) {
    const double c = std::cos(-b.yaw_rad), s = std::sin(-b.yaw_rad);
    const double lx = c * (x - b.center.x()) - s * (y - b.center.y());
    const double ly = s * (x - b.center.x()) + c * (y - b.center.y());
    if (std::abs(lx) <= b.half_extents.x() && std::abs(ly) <= b.half_extents.y()) h = std::max(h, b.center.z() + b.half_extents.z());
  }
  return h;
}

std::array<double, 25> Terrain::height_map(double x, double y, double yaw_rad, double spacing_m, double reference_z) const {
  std::array<double, 25> out{};
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  for (int a = 0; a < 5; ++a) {
    for (int b = 0; b < 5; ++b) {
      const double u = (a - 2) * spacing_m, v = (b - 2) * spacing_m;
      out[a * 5 + b] = height(x + c * u - s * v, y + s * u + c * v) - reference_z;
    }
  }
  return out;
}

}  // namespace podium::sim
