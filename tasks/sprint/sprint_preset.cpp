// The sprint's presets, read from data (sprint seed §2; the numbers are ours, see README.md).
#include "sprint_preset.h"

#include "podium/base/error.h"
#include "podium/base/json.h"

namespace podium::tasks::sprint {
namespace {

Range read_range(base::ConfigReader& r, const std::string& key, Range fallback, const std::string& doc) {
  const std::vector<double> v = r.numbers(key, {fallback.lo, fallback.hi}, {}, doc);
  if (v.size() != 2 || v[0] > v[1]) r.fail(key, "must be [lo, hi] with lo ≤ hi");
  return {v[0], v[1]};
}

}  // namespace

SprintPreset read_sprint_preset(base::ConfigReader& r) {
  SprintPreset p;
  r.object("track", [&](base::ConfigReader& t) {
    p.track.length_m = t.number("length_m", p.track.length_m, {0.0, 1000.0, true}, "L: the finish plane's x, m");
    p.track.lane_width_m = t.number("lane_width_m", p.track.lane_width_m, {0.0, 10.0, true}, "lane width, m");
  });
  r.object("steps", [&](base::ConfigReader& s) {
    p.steps.debounce = s.integer<int>("debounce", p.steps.debounce, {1, 1000}, "observations in contact that make a touchdown");
    p.steps.n_norm = s.number("n_norm", p.steps.n_norm, {0.0, 1e6, true}, "N_norm: z = steps / N_norm");
  });
  r.object("rewards", [&](base::ConfigReader& w) {
    RewardWeights& x = p.rewards;
    x.forward = w.number("forward", x.forward, {0.0, 1e3}, "w_f, per m/s");
    x.survival = w.number("survival", x.survival, {0.0, 1e3}, "r_s per control step");
    x.lateral = w.number("lateral", x.lateral, {0.0, 1e3}, "w_d: r_d at the lane's edge is −w_d");
    x.mass = w.number("mass", x.mass, {0.0, 1e3}, "w_m, per m of COM gap");
    x.mirror = w.number("mirror", x.mirror, {0.0, 1e3}, "w_mirror");
    x.mirror_k = w.number("mirror_k", x.mirror_k, {0.0, 1e3}, "k of r_mirror, per rad²");
    x.diagonal = w.number("diagonal", x.diagonal, {0.0, 1e3}, "w_diag");
    x.diagonal_k = w.number("diagonal_k", x.diagonal_k, {0.0, 1e3}, "k_diag, per rad²");
  });
  r.object("drag", [&](base::ConfigReader& d) {
    p.drag.air_density = d.number("air_density", p.drag.air_density, {0.0, 10.0}, "ρ, kg/m³");
    p.drag.cda_m2 = d.number("cda_m2", p.drag.cda_m2, {0.0, 10.0}, "whole-body C_d·A, m²");
  });
  r.object("randomise", [&](base::ConfigReader& d) {
    p.wind_mps = read_range(d, "wind_mps", p.wind_mps, "wind along the track, m/s, U(lo, hi)");
    p.friction = read_range(d, "friction", p.friction, "runway μ, U(lo, hi)");
  });
  r.object("episode", [&](base::ConfigReader& e) {
    p.time_limit_s = e.number("time_limit_s", p.time_limit_s, {0.0, 3600.0, true}, "an episode is truncated after this long, s");
  });
  return p;
}

EpisodeDraw draw_episode(const SprintPreset& preset, base::Rng& rng) {
  EpisodeDraw d;
  d.wind_mps = rng.uniform(preset.wind_mps.lo, preset.wind_mps.hi);
  d.friction = rng.uniform(preset.friction.lo, preset.friction.hi);
  return d;
}

std::string sprint_presets_file() { return std::string(PODIUM_SPRINT_DATA_DIR) + "/presets.json"; }

SprintPreset load_sprint_preset(const std::string& name) {
  const std::string file = sprint_presets_file();
  const base::Json all = base::read_json_file(file);
  if (!all.is_object() || !all.contains(name)) throw base::UserError(file + ": no preset \"" + name + "\"");
  base::ConfigReader reader(all.at(name), name, file);
  SprintPreset preset = read_sprint_preset(reader);
  reader.finish();
  return preset;
}

}  // namespace podium::tasks::sprint
