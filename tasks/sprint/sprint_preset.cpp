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

void read_start(base::ConfigReader& r, StartPreset& s) {
  s.imitation_weight = r.number("imitation_weight", s.imitation_weight, {0.0, 1e3}, "λ_i: the reward is r_base + λ_i·r_I");
  character::ImitationWeights& w = s.weights;
  w.pose = r.number("pose", w.pose, {0.0, 1e3}, "w_p of r_I (joint rotations)");
  w.velocity = r.number("velocity", w.velocity, {0.0, 1e3}, "w_v of r_I (joint rates)");
  w.end_effector = r.number("end_effector", w.end_effector, {0.0, 1e3}, "w_e of r_I (end effectors)");
  w.com = r.number("com", w.com, {0.0, 1e3}, "w_c of r_I (centre of mass)");
  w.pose_scale =
      r.number("pose_scale", w.pose_scale, {0.0, 1e4}, "r_p = exp(−this·Σ_j ŵ_j‖q̂_j ⊖ q_j‖²) (character/imitation.h), per rad²");
  w.velocity_scale = r.number("velocity_scale", w.velocity_scale, {0.0, 1e4}, "r_v's kernel, per (rad/s)²");
  w.end_effector_scale =
      r.number("end_effector_scale", w.end_effector_scale, {0.0, 1e4}, "r_e's kernel (end effectors from the root), per m²");
  w.com_scale = r.number("com_scale", w.com_scale, {0.0, 1e4}, "r_c's kernel, per m²");
  s.max_com_deviation_m = r.number("max_com_deviation_m", s.max_com_deviation_m, {0.0, 100.0, true},
                                   "early termination: the COM this far from the reference's, m");
  s.min_pose_reward =
      r.number("min_pose_reward", s.min_pose_reward, {0.0, 1.0}, "early termination: r_p at most this (0: never)");
  s.landing_x_m = r.number("landing_x_m", s.landing_x_m, {0.0, 10.0, true}, "the references' first landing, m past the line");
  s.extra_time_s = r.number("extra_time_s", s.extra_time_s, {0.0, 60.0},
                            "a Start not landed by its reference's duration plus this has failed, s");
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
  r.object("start", [&](base::ConfigReader& s) { read_start(s, p.start); });
  r.object("race", [&](base::ConfigReader& s) {
    p.race.episodes = s.integer<int>("episodes", p.race.episodes, {1, 1'000'000}, "the race report's DR episodes");
  });
  r.object("dip", [&](base::ConfigReader& d) {
    p.dip.fall_penalty_s = d.number("fall_penalty_s", p.dip.fall_penalty_s, {0.0, 1e5, true},
                                    "the dip: an episode that does not finish scores this time from its snapshot, s");
  });
  if (!(p.dip.fall_penalty_s > p.time_limit_s))
    r.fail("dip", "fall_penalty_s " + base::Json(p.dip.fall_penalty_s).dump() + " must exceed episode.time_limit_s " +
                      base::Json(p.time_limit_s).dump() + " (every finisher must beat every fall)");
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
