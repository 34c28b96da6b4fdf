#pragma once
/// The terrain of the curve get-up (seed §3.2, §5.4): one world in four regions of rising
/// difficulty — flat, easy, medium, hard — and where an episode's drop lands in each. The seed
/// gives the tile size (1 m), the steepest slope (30°) and Fig. 3's three slopes and three
/// roughness levels, not their values: the tile heights and slopes here (±2/±5/±10 cm, 10°/20°/30°)
/// are ours, preset data. Written here: no library lays out such a course.
///
/// Level 0, flat, is the plane around the origin. Level k ≥ 1 is a `size_m` square centred at
/// (k·spacing_m, 0), its half y < 0 rough (1 m tiles, heights uniform in ±tile_height_m) and its
/// half y ≥ 0 a slope rising along +x at slope_deg from the ground at its near edge. A drop on
/// level k lands uniformly inside one of its two parts (either, equally likely), `margin_m` from
/// the part's edges; on flat, at the origin.
#include <cstdint>
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "podium/base/rng.h"
#include "podium/sim/terrain.h"

namespace podium::tasks::getup_curves {

struct TerrainLevel {
  std::string name;
  double tile_height_m = 0.0;  ///< rough tiles' heights are uniform in ±this
  double slope_deg = 0.0;      ///< the slope part's incline
};

struct TerrainLevels {
  int levels = 1;  ///< how many of `specs` the world holds (1: flat only)
  std::vector<TerrainLevel> specs = {{"flat", 0.0, 0.0}, {"easy", 0.02, 10.0}, {"medium", 0.05, 20.0}, {"hard", 0.10, 30.0}};
  double size_m = 10.0;           ///< each harder level's square
  double spacing_m = 20.0;        ///< between level centres along +x
  double margin_m = 1.5;          ///< drops land this far inside a part's edges
  int successes_to_unlock = 200;  ///< §5.4: successes on the newest level that unlock the next
  /// §6.4's "no terrain curriculum" ablation: > 0 opens the next level every this many control
  /// steps of training instead (the seed: one region per 20M simulation steps = 10M control steps).
  std::int64_t schedule_steps = 0;
  std::uint64_t seed = 1;  ///< the tiles' heights
};

/// Reads the `terrain_*` keys (errors name the JSON path and the value).
void read_terrain_levels(base::ConfigReader& r, TerrainLevels& t);

/// The world's regions: two per level above flat (rough, then slope).
sim::TerrainConfig terrain_config(const TerrainLevels& t);

/// Where a drop on `level` is released (x, y), uniformly inside one of its parts (none drawn on flat).
struct DropSite {
  double x_m = 0.0, y_m = 0.0;
};
DropSite drop_site(const TerrainLevels& t, int level, base::Rng& rng);

}  // namespace podium::tasks::getup_curves
