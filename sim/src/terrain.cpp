#include "podium/sim/terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "podium/base/error.h"
#include "podium/base/rng.h"

namespace podium::sim {

namespace {

// Top of a box along the vertical line through (x, y), or −∞ when the line misses it: the line
// z ↦ (x, y, z) in box coordinates is o + z·d, clipped against the three slabs (Kay–Kajiya).
double box_top(const Eigen::Vector3d& center, const Eigen::Vector3d& half, const Eigen::Quaterniond& rotation, double x,
               double y) {
  const Eigen::Matrix3d Rt = rotation.toRotationMatrix().transpose();
  const Eigen::Vector3d o = Rt * (Eigen::Vector3d(x, y, 0.0) - center), d = Rt.col(2);
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d(k)) < 1e-12) {
      if (std::abs(o(k)) > half(k)) return -std::numeric_limits<double>::infinity();
      continue;
    }
    double a = (-half(k) - o(k)) / d(k), b = (half(k) - o(k)) / d(k);
    if (a > b) std::swap(a, b);
    lo = std::max(lo, a);
    hi = std::min(hi, b);
  }
  return lo <= hi ? hi : -std::numeric_limits<double>::infinity();
}

std::string region_name(std::size_t r) { return "terrain.regions[" + std::to_string(r) + "]"; }

}  // namespace

TerrainConfig TerrainConfig::rough(const std::string& level, std::uint64_t seed) {
  TerrainRegion r;
  r.kind = TerrainRegion::Kind::rough;
  r.seed = seed;
  if (level == "easy") r.max_tile_height_m = 0.05;
  else if (level == "medium") r.max_tile_height_m = 0.10;
  else if (level == "hard") r.max_tile_height_m = 0.20;
  else throw base::UserError("sim: terrain level \"" + level + "\" is not one of easy, medium, hard");
  TerrainConfig c;
  c.regions.push_back(r);
  return c;
}

Terrain::Terrain(TerrainConfig config) : config_(std::move(config)) {
  for (std::size_t r = 0; r < config_.regions.size(); ++r) {
    const TerrainRegion& g = config_.regions[r];
    const std::string where = "sim: " + region_name(r);
    if (!(g.min.array() < g.max.array()).all()) throw base::UserError(where + ": min must be below max in x and y");
    for (std::size_t o = 0; o < r; ++o) {
      const TerrainRegion& h = config_.regions[o];
      if ((g.min.array() < h.max.array()).all() && (h.min.array() < g.max.array()).all())
        throw base::UserError(where + ": overlaps " + region_name(o));
    }
    const Eigen::Vector2d size = g.max - g.min;
    std::vector<double> heights;
    std::array<int, 2> counts{0, 0};
    if (g.kind == TerrainRegion::Kind::flat) {
      pieces_.push_back(
          {static_cast<int>(r), Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 0), Eigen::Quaterniond::Identity()});
      const double bottom = std::min(g.height_m, 0.0) - kPieceDepthM;
      pieces_.back().center << 0.5 * (g.min + g.max), 0.5 * (g.height_m + bottom);
      pieces_.back().half_extents << 0.5 * size, 0.5 * (g.height_m - bottom);
    } else if (g.kind == TerrainRegion::Kind::rough) {
      if (!(g.tile_size_m > 0)) throw base::UserError(where + ".tile_size_m: " + std::to_string(g.tile_size_m) + " is not > 0");
      if (g.min_tile_height_m > g.max_tile_height_m)
        throw base::UserError(where + ": min_tile_height_m is above max_tile_height_m");
      counts = {static_cast<int>(std::ceil(size.x() / g.tile_size_m - 1e-9)),
                static_cast<int>(std::ceil(size.y() / g.tile_size_m - 1e-9))};
      base::Rng rng(g.seed);
      heights.resize(static_cast<std::size_t>(counts[0]) * counts[1]);
      for (double& h : heights) h = rng.uniform(g.min_tile_height_m, g.max_tile_height_m);
      for (int i = 0; i < counts[0]; ++i) {
        for (int j = 0; j < counts[1]; ++j) {
          const double h = heights[static_cast<std::size_t>(i) * counts[1] + j], bottom = std::min(h, 0.0) - kPieceDepthM;
          const Eigen::Vector2d lo = g.min + g.tile_size_m * Eigen::Vector2d(i, j);
          const Eigen::Vector2d hi = (lo + Eigen::Vector2d::Constant(g.tile_size_m)).cwiseMin(g.max);
          TerrainPiece p{static_cast<int>(r), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()};
          p.center << 0.5 * (lo + hi), 0.5 * (h + bottom);
          p.half_extents << 0.5 * (hi - lo), 0.5 * (h - bottom);
          pieces_.push_back(p);
        }
      }
    } else {
      if (!(std::abs(g.slope_rad) < std::numbers::pi / 2)) throw base::UserError(where + ".slope_rad: |slope| must be below π/2");
      // An inclined box whose top face spans the region: low edge at x = min.x, height height_m.
      const double c = std::cos(g.slope_rad), s = std::sin(g.slope_rad), half_len = 0.5 * size.x() / c;
      const Eigen::Quaterniond rot(Eigen::AngleAxisd(-g.slope_rad, Eigen::Vector3d::UnitY()));  // +x tilts up
      const Eigen::Vector3d top_centre(0.5 * (g.min.x() + g.max.x()), 0.5 * (g.min.y() + g.max.y()),
                                       g.height_m + 0.5 * size.x() * std::tan(g.slope_rad));
      const Eigen::Vector3d normal(-s, 0.0, c);
      pieces_.push_back({static_cast<int>(r), top_centre - 0.5 * kPieceDepthM * normal,
                         Eigen::Vector3d(half_len, 0.5 * size.y(), 0.5 * kPieceDepthM), rot});
    }
    tiles_.push_back(std::move(heights));
    tile_counts_.push_back(counts);
  }
  for (std::size_t b = 0; b < config_.boxes.size(); ++b)
    if ((config_.boxes[b].half_extents.array() <= 0).any())
      throw base::UserError("sim: terrain.boxes[" + std::to_string(b) + "] (\"" + config_.boxes[b].name +
                            "\").half_extents: an entry is ≤ 0");
}

double Terrain::tile_height(int r, int i, int j) const { return tiles_[r][static_cast<std::size_t>(i) * tile_counts_[r][1] + j]; }

int Terrain::region_at(double x, double y) const {
  for (std::size_t r = 0; r < config_.regions.size(); ++r) {
    const TerrainRegion& g = config_.regions[r];
    if (x >= g.min.x() && x < g.max.x() && y >= g.min.y() && y < g.max.y()) return static_cast<int>(r);
  }
  return -1;
}

double Terrain::height(double x, double y) const {
  double h = 0.0;
  if (const int r = region_at(x, y); r >= 0) {
    const TerrainRegion& g = config_.regions[r];
    switch (g.kind) {
      case TerrainRegion::Kind::flat:
        h = g.height_m;
        break;
      case TerrainRegion::Kind::slope:
        h = g.height_m + (x - g.min.x()) * std::tan(g.slope_rad);
        break;
      case TerrainRegion::Kind::rough: {
        const int i = std::min(static_cast<int>((x - g.min.x()) / g.tile_size_m), tile_counts_[r][0] - 1);
        const int j = std::min(static_cast<int>((y - g.min.y()) / g.tile_size_m), tile_counts_[r][1] - 1);
        h = tile_height(r, i, j);
        break;
      }
    }
  }
  for (const BoxProp& b : config_.boxes) h = std::max(h, box_top(b.center, b.half_extents, b.rotation, x, y));
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
