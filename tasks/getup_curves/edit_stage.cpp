// The curve-edit stage (edit_stage.h). Written here: no library evaluates style-curve edits.
#include "edit_stage.h"

#include <algorithm>
#include <array>
#include <numbers>

#include "curve_edit.h"
#include "curve_env.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/sim/model.h"

namespace podium::tasks::getup_curves {

using base::Json;
namespace fs = std::filesystem;

namespace {

constexpr int kKnots = 9;
constexpr double kDeg = 180.0 / std::numbers::pi;
// Features in cm and degrees: comparable steps, so one Euclidean threshold tells styles apart.
constexpr double kUnit[3] = {100.0, kDeg, kDeg};

// The achieved features at the knots t = T·j/8 of each episode: the first control step at or past
// each knot (an episode that ended before a knot keeps its last value there).
struct KnotSamples {
  double duration_s;
  std::vector<std::array<std::array<double, kKnots>, 3>> per_episode;
  std::vector<int> next;  // per episode: the next knot to fill
  void add(std::size_t start, const CurveGetupEnv& env) {
    if (per_episode.size() <= start) per_episode.resize(start + 1), next.resize(start + 1, 0);
    const StyleFeatures w = env.achieved();
    auto& knots = per_episode[start];
    int& j = next[start];
    while (j < kKnots && env.curve_time_s() + 1e-9 >= duration_s * j / (kKnots - 1)) {
      for (int f = 0; f < 3; ++f) knots[static_cast<std::size_t>(f)][static_cast<std::size_t>(j)] = w(f) * kUnit[f];
      ++j;
    }
    for (int k = j; k < kKnots; ++k)  // not reached yet: the latest value until it is
      for (int f = 0; f < 3; ++f) knots[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] = w(f) * kUnit[f];
  }
  std::vector<double> mean() const {
    std::vector<double> out(3 * kKnots, 0.0);
    for (const auto& e : per_episode)
      for (int f = 0; f < 3; ++f)
        for (int j = 0; j < kKnots; ++j)
          out[static_cast<std::size_t>(f * kKnots + j)] += e[static_cast<std::size_t>(f)][static_cast<std::size_t>(j)];
    for (double& v : out) v /= static_cast<double>(std::max<std::size_t>(1, per_episode.size()));
    return out;
  }
};

}  // namespace

void read_edit_settings(base::ConfigReader& r, EditSettings& s) {
  s.base_curve = r.string("edit_base_curve", s.base_curve,
                          "edit stage: the curve edited (a shipped name, tasks/getup_curves/data/curves/<name>.json, or a "
                          "path)");
  s.point =
      r.integer<int>("edit_point", s.point, {0, kKnots - 1}, "edit stage: the control point of h the param h_offset_m moves");
  s.episodes = r.integer<int>("edit_episodes", s.episodes, {0, 10'000},
                              "edit stage: test episodes per edit, from the test starts (0: test_starts)");
  s.shipped_policy = r.file("edit_shipped_policy", s.shipped_policy,
                            "edit stage without an input train trial: a shipped policy (TorchScript, e.g. "
                            "tasks/getup_curves/policies/) to run on the edits");
  s.shipped_cvae = r.file("edit_shipped_cvae", s.shipped_cvae,
                          "edit stage with edit_shipped_policy: the pose C-VAE it acts through (actions \"cvae\"); empty: "
                          "it acts on PD targets");
  if (!s.shipped_cvae.empty() && s.shipped_policy.empty()) r.fail("edit_shipped_cvae", "is set without edit_shipped_policy");
}

Json edit_params() {
  return {{{"name", "rise_fraction"}, {"low", 0.3}, {"high", 0.9}},
          {{"name", "h_offset_m"}, {"low", -0.3}, {"high", 0.3}},
          {{"name", "duration_scale"}, {"low", 0.8}, {"high", 1.5}}};
}

StyleCurve edited_curve(const StyleCurve& base, const CurveEdit& edit, int point) {
  const double shift = edit.rise_fraction > 0.0 ? edit.rise_fraction * base.duration_s - rise_time_s(base) : 0.0;
  StyleCurve c = shift != 0.0 ? shift_rise(base, shift) : base;
  if (edit.h_offset_m != 0.0) c = move_control_point(c, "h", point, edit.h_offset_m);
  if (edit.duration_scale != 1.0) c = scale_duration(c, edit.duration_scale);
  c.name = base.name + "+edit";
  c.source = base.name + " with its rise at " + std::to_string(edit.rise_fraction) + " of T (" + std::to_string(shift) +
             " s later), h's control point " + std::to_string(point) + " moved " + std::to_string(edit.h_offset_m) + " m, T × " +
             std::to_string(edit.duration_scale) + " (the edit stage)";
  return c;
}

Json edit_features() {
  Json out = Json::array();
  const std::array<std::array<const char*, 3>, 3> rows = {{{"h", "cm", "neck-base height"},
                                                           {"theta_x", "°", "side vector's angle to up"},
                                                           {"theta_z", "°", "front vector's angle to up"}}};
  for (std::size_t f = 0; f < 3; ++f)
    for (int j = 0; j < kKnots; ++j)
      out.push_back({{"name", std::string(rows[f][0]) + "_" + std::to_string(j)},
                     {"low", 0.0},
                     {"high", f == 0 ? 200.0 : 180.0},
                     {"metric", "euclidean"},
                     {"unit", rows[f][1]},
                     {"description",
                      std::string("achieved ") + rows[f][2] + " at t = T·" + std::to_string(j) + "/8 (mean over the episodes)"}});
  return out;
}

EditOutcome run_curve_edit(const TrainSettings& train, const EditSettings& settings, const CurveEdit& edit,
                           const character::PolicyFn& policy, const fs::path& work_dir) {
  TrainSettings base = train;
  base.curves = {settings.base_curve};
  const fs::path file = curve_files(base).at(0);
  const std::shared_ptr<const CurveSet> loaded = load_curve_set({file}, sim::load_shipped_model("humanoid34"));
  auto set = std::make_shared<CurveSet>(*loaded);
  EditOutcome out;
  out.curve = set->curves.at(0) = edited_curve(loaded->curves.at(0), edit, settings.point);
  out.curve_file = work_dir / "edited_curve.json";
  base::write_json_file_atomic(out.curve_file, style_curve_json(out.curve));
  CurveGetupEnv env(train.env, set);
  KnotSamples knots{out.curve.duration_s, {}, {}};
  const int episodes = settings.episodes > 0 ? settings.episodes : train.test_starts;
  out.test = test_curves(env, policy, episodes, train.test_seed,
                         [&](std::size_t start, const CurveGetupEnv& e) { knots.add(start, e); });
  out.features = knots.mean();
  env.use_curve(0);
  const Json entry = record_curve_episode(env, policy, base::derive_seed(train.test_seed, 0), work_dir / "rollouts", "trajectory",
                                          out.trajectory);
  out.curves = work_dir / "curves.json";
  base::write_json_file_atomic(out.curves, {{"control_hz", train.env.control_hz}, {"episodes", Json::array({entry})}});
  return out;
}

}  // namespace podium::tasks::getup_curves
