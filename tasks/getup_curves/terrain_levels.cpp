// The curve get-up's terrain levels (terrain_levels.h).
#include "terrain_levels.h"

#include <cmath>
#include <numbers>

#include "podium/base/error.h"

namespace podium::tasks::getup_curves {

void read_terrain_levels(base::ConfigReader& r, TerrainLevels& t) {
  t.levels = r.integer<int>("terrain_levels", t.levels, {1, static_cast<int>(t.specs.size())},
                            "terrain regions in the world, of flat, easy, medium, hard (§3.2, §5.4; 1: flat only)");
  t.successes_to_unlock = r.integer<int>("terrain_successes_to_unlock", t.successes_to_unlock, {1, 1'000'000},
                                         "successes on the newest open region that open the next (§5.4: 200)");
  t.size_m = r.number("terrain_size_m", t.size_m, {.min = 2.0 * t.margin_m, .max = 1000.0, .exclusive_min = true},
                      "side of each harder region's square (half rough, half slope), m");
  t.seed = r.integer<std::uint64_t>("terrain_seed", t.seed, {}, "the rough tiles' heights");
  t.schedule_steps = r.integer<std::int64_t>(
      "terrain_schedule_steps", t.schedule_steps, {.min = 0},
      "> 0: §6.4's ablation, a fixed schedule opening the next region every this many control steps (the seed: 20M "
      "simulation steps, 10M control steps) instead of the successes; 0: the curriculum");
}

namespace {

double centre_x(const TerrainLevels& t, int level) { return t.spacing_m * level; }

}  // namespace

sim::TerrainConfig terrain_config(const TerrainLevels& t) {
  if (t.levels < 1 || t.levels > static_cast<int>(t.specs.size()))
    throw base::UserError("curve get-up terrain: " + std::to_string(t.levels) + " levels of " + std::to_string(t.specs.size()));
  if (!(t.spacing_m > t.size_m)) throw base::UserError("curve get-up terrain: levels overlap (spacing ≤ size)");
  sim::TerrainConfig c;
  const double h = 0.5 * t.size_m;
  for (int k = 1; k < t.levels; ++k) {
    const TerrainLevel& l = t.specs[static_cast<std::size_t>(k)];
    const double x0 = centre_x(t, k) - h, x1 = centre_x(t, k) + h;
    sim::TerrainRegion rough;
    rough.kind = sim::TerrainRegion::Kind::rough;
    rough.min = {x0, -h}, rough.max = {x1, 0.0};
    rough.tile_size_m = 1.0;
    rough.min_tile_height_m = -l.tile_height_m, rough.max_tile_height_m = l.tile_height_m;
    rough.seed = base::derive_seed(t.seed, static_cast<std::uint64_t>(k));
    sim::TerrainRegion slope;
    slope.kind = sim::TerrainRegion::Kind::slope;
    slope.min = {x0, 0.0}, slope.max = {x1, h};
    slope.slope_rad = l.slope_deg * std::numbers::pi / 180.0;
    c.regions.push_back(rough);
    c.regions.push_back(slope);
  }
  return c;
}

DropSite drop_site(const TerrainLevels& t, int level, base::Rng& rng) {
  if (level <= 0) return {};
  const double h = 0.5 * t.size_m, m = t.margin_m;
  const bool slope = rng.uniform(0.0, 1.0) < 0.5;
  DropSite d;
  d.x_m = rng.uniform(centre_x(t, level) - h + m, centre_x(t, level) + h - m);
  d.y_m = slope ? rng.uniform(m, h - m) : rng.uniform(-h + m, -m);
  return d;
}

}  // namespace podium::tasks::getup_curves
