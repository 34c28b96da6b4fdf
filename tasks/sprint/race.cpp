// The race report (sprint seed §3: Start §3.1 → Acceleration + Top Speed §3.2 → the dip §3.3),
// its per-episode measures and the paired wind check.
#include "race.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>

#include "crouch_start.h"
#include "dip.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/learn/frozen_policy.h"
#include "podium/sim/recorder.h"
#include "run_metrics.h"
#include "sprint_env.h"
#include "track.h"
#include "train_start.h"

namespace podium::tasks::sprint {

using base::Json;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

double mean_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double std_of(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean_of(v);
  double s = 0.0;
  for (const double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

Json optional_json(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

// A result table's column (plugins/task.h "Result tables"; the plugin layer is not a dependency here).
Json column(const std::string& name, const std::string& unit = "") {
  Json c = {{"name", name}};
  if (!unit.empty()) c["unit"] = unit;
  return c;
}

double symmetry_index(double left, double right) {
  return left + right > 0.0 ? std::abs(left - right) / (0.5 * (left + right)) : 0.0;
}

}  // namespace

std::vector<double> split_times(const std::vector<double>& t_s, const std::vector<double>& front_x_m, double split_m,
                                double length_m, std::optional<double> finish_s) {
  if (t_s.size() != front_x_m.size())
    throw base::UserError("race splits: " + std::to_string(t_s.size()) + " times but " + std::to_string(front_x_m.size()) +
                          " positions");
  if (!(split_m > 0.0)) throw base::UserError("race splits: split_m " + std::to_string(split_m) + " is not > 0");
  std::vector<double> splits;
  std::size_t i = 0;
  for (int k = 1; k * split_m < length_m - 1e-9; ++k) {
    const double mark = k * split_m;
    std::optional<double> t;
    for (; i < t_s.size() && !t; ++i)
      t = crossing_time(t_s[i > 0 ? i - 1 : 0], front_x_m[i > 0 ? i - 1 : 0], t_s[i], front_x_m[i], mark);
    if (!t) break;
    splits.push_back(*t);
    --i;  // the next mark may be crossed within the same interval
  }
  if (finish_s) splits.push_back(*finish_s);
  return splits;
}

std::vector<SegmentSteps> steps_by_segment(const std::vector<Touchdown>& touchdowns, double segment_m, double length_m) {
  if (!(segment_m > 0.0)) throw base::UserError("race steps: segment_m " + std::to_string(segment_m) + " is not > 0");
  std::vector<SegmentSteps> segments;
  for (double from = 0.0; from < length_m - 1e-9; from += segment_m)
    segments.push_back({from, std::min(from + segment_m, length_m)});
  std::vector<double> time(segments.size(), 0.0), length(segments.size(), 0.0);
  for (std::size_t i = 1; i < touchdowns.size(); ++i) {
    const double x = touchdowns[i].x_m;
    if (x < 0.0 || x >= length_m) continue;
    const auto s = std::min(segments.size() - 1, static_cast<std::size_t>(x / segment_m));
    ++segments[s].steps;
    length[s] += x - touchdowns[i - 1].x_m;
    time[s] += touchdowns[i].t_s - touchdowns[i - 1].t_s;
  }
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (segments[s].steps == 0) continue;
    segments[s].length_m = length[s] / segments[s].steps;
    segments[s].frequency_hz = time[s] > 0.0 ? segments[s].steps / time[s] : 0.0;
  }
  return segments;
}

Json StepAsymmetry::to_json() const {
  return {{"left_steps", left_steps},         {"right_steps", right_steps},   {"left_length_m", left_length_m},
          {"right_length_m", right_length_m}, {"length_index", length_index}, {"left_time_s", left_time_s},
          {"right_time_s", right_time_s},     {"time_index", time_index}};
}

StepAsymmetry step_asymmetry(const std::vector<Touchdown>& touchdowns) {
  std::vector<double> length[2], time[2];
  for (std::size_t i = 1; i < touchdowns.size(); ++i) {
    const int side = touchdowns[i].foot == Foot::left ? 0 : 1;
    length[side].push_back(touchdowns[i].x_m - touchdowns[i - 1].x_m);
    time[side].push_back(touchdowns[i].t_s - touchdowns[i - 1].t_s);
  }
  StepAsymmetry a;
  a.left_steps = static_cast<int>(length[0].size()), a.right_steps = static_cast<int>(length[1].size());
  a.left_length_m = mean_of(length[0]), a.right_length_m = mean_of(length[1]);
  a.left_time_s = mean_of(time[0]), a.right_time_s = mean_of(time[1]);
  if (a.left_steps > 0 && a.right_steps > 0) {
    a.length_index = symmetry_index(a.left_length_m, a.right_length_m);
    a.time_index = symmetry_index(a.left_time_s, a.right_time_s);
  }
  return a;
}

std::vector<double> lean_per_step(const std::vector<Touchdown>& touchdowns, const std::vector<double>& lean_rad) {
  std::vector<double> out;
  for (std::size_t i = 0; i < touchdowns.size(); ++i) {
    const std::size_t from = touchdowns[i].sample, to = i + 1 < touchdowns.size() ? touchdowns[i + 1].sample : lean_rad.size();
    if (from >= to || to > lean_rad.size())
      throw base::UserError("race lean: touchdown " + std::to_string(i) + " at sample " + std::to_string(from) +
                            " is not before " + std::to_string(to) + " (of " + std::to_string(lean_rad.size()) + " samples)");
    out.push_back(std::accumulate(lean_rad.begin() + static_cast<std::ptrdiff_t>(from),
                                  lean_rad.begin() + static_cast<std::ptrdiff_t>(to), 0.0) /
                  static_cast<double>(to - from));
  }
  return out;
}

std::vector<std::optional<double>> speed_profile(const std::vector<double>& t_s, const std::vector<double>& x_m, double bin_m,
                                                 double length_m) {
  if (!(bin_m > 0.0)) throw base::UserError("race speed profile: bin_m " + std::to_string(bin_m) + " is not > 0");
  std::vector<std::optional<double>> out;
  for (double from = 0.0; from < length_m - 1e-9; from += bin_m)
    out.push_back(segment_speed(t_s, x_m, from, std::min(from + bin_m, length_m)));
  return out;
}

std::optional<SpeedPeak> top_speed(const std::vector<double>& t_s, const std::vector<double>& x_m, double window_m,
                                   double step_m) {
  if (!(window_m > 0.0 && step_m > 0.0)) throw base::UserError("race top speed: window and step must be > 0");
  std::optional<SpeedPeak> best;
  if (x_m.empty()) return best;
  const double end = *std::max_element(x_m.begin(), x_m.end());
  for (double from = 0.0; from + window_m <= end + 1e-12; from += step_m)
    if (const auto v = segment_speed(t_s, x_m, from, from + window_m); v && (!best || *v > best->speed_mps))
      best = SpeedPeak{*v, from + 0.5 * window_m};
  return best;
}

void read_race_settings(base::ConfigReader& r, RaceSettings& s) {
  s.episodes = r.integer<int>("race_episodes", s.episodes, {0, 1'000'000}, "race: DR episodes (0: the preset's race.episodes)");
  s.seed = r.integer<std::uint64_t>("race_seed", s.seed, {},
                                    "race: the episodes' seeds and draws derive from it (keep it apart from eval_seed)");
  const double d = r.number("race_dip_distance_m", s.dip ? s.dip->distance_m : 0.0, {0.0, 1000.0},
                            "race: d_dip, the dip fires at the first control step with the root this close to the line, m "
                            "(0: no dip, unless a dip trial is an input)");
  const double theta = r.number("race_dip_angle_deg", s.dip ? s.dip->angle_deg : 0.0, {0.0, 90.0},
                                "race: θ_dip, added to both hips' flexion targets from then on, degrees");
  if (d > 0.0) s.dip = DipParams{d, theta};
  s.wind_check = r.boolean("race_wind_check", s.wind_check, "race: also run every episode in a headwind and a tailwind");
  s.wind_check_mps = r.number("race_wind_check_mps", s.wind_check_mps, {0.0, 50.0, true},
                              "race: the wind check's wind, −this and +this m/s (μ as drawn)");
  s.split_m = r.number("race_split_m", s.split_m, {0.0, 1000.0, true}, "race: splits and step segments every this many m");
  s.profile_bin_m = r.number("race_profile_bin_m", s.profile_bin_m, {0.0, 1000.0, true}, "race: the speed profile's bin, m");
  s.top_speed_window_m = r.number("race_top_speed_window_m", s.top_speed_window_m, {0.0, 1000.0, true},
                                  "race: the top speed is the highest mean speed over a window this long, m");
  s.record = r.integer<int>("race_record", s.record, {0, 1000}, "race: motions written (the first DR episodes)");
}

}  // namespace podium::tasks::sprint

// ---- Per episode ---------------------------------------------------------------------------------

namespace podium::tasks::sprint {

Json RaceEpisode::to_json() const {
  Json segs = Json::array();
  for (const SegmentSteps& s : segments)
    segs.push_back({{"from_m", s.from_m},
                    {"to_m", s.to_m},
                    {"steps", s.steps},
                    {"step_length_m", s.steps > 0 ? Json(s.length_m) : Json(nullptr)},
                    {"step_frequency_hz", s.steps > 0 ? Json(s.frequency_hz) : Json(nullptr)}});
  Json profile = Json::array();
  for (const auto& v : speed_profile_mps) profile.push_back(optional_json(v));
  Json lean = Json::array();
  for (const double l : lean_per_step_rad) lean.push_back(l * kDeg);
  return {{"index", index},
          {"seed", seed},
          {"draw", draw.to_json()},
          {"reference", reference},
          {"outcome", outcome},
          {"finish_time_s", optional_json(finish_time_s)},
          {"landing_time_s", optional_json(landing_time_s)},
          {"distance_m", distance_m},
          {"splits_s", splits_s},
          {"speed_profile_mps", profile},
          {"top_speed_mps", top_speed ? Json(top_speed->speed_mps) : Json(nullptr)},
          {"top_speed_at_m", top_speed ? Json(top_speed->at_m) : Json(nullptr)},
          {"steps", steps},
          {"step_length_m", steps > 1 ? Json(step_length_m) : Json(nullptr)},
          {"step_frequency_hz", steps > 1 ? Json(step_frequency_hz) : Json(nullptr)},
          {"segments", segs},
          {"lean_per_step_deg", lean},
          {"first_segment_lean_deg", first_segment_lean_rad * kDeg},
          {"rise_distance_m", optional_json(rise_distance_m)},
          {"asymmetry", asymmetry.to_json()},
          {"dip_x_m", optional_json(dip_x_m)}};
}

namespace {

// One sample per control step of both phases, and the counted touchdowns.
struct Trace {
  std::vector<double> t_s, root_x, front_x, lean;
  std::vector<Touchdown> touchdowns;
  int steps = 0;
};

double trunk_lean(const SprintEnv& env) {
  const Eigen::Matrix3d& R = env.world().data().links[static_cast<std::size_t>(env.model().torso_body())].R;
  return std::acos(std::clamp(R(2, 2), -1.0, 1.0));  // the torso's up axis from +z, as the accelerate stage's
}

void take_sample(const SprintEnv& env, Trace& tr) {
  const double t = env.world().time_s();
  tr.t_s.push_back(t);
  tr.root_x.push_back(env.world().data().q(0));
  tr.front_x.push_back(env.finish_line().front_x());
  tr.lean.push_back(trunk_lean(env));
  const int steps = env.step_counter().steps();
  if (steps > tr.steps && env.step_counter().last_foot()) {
    const Foot foot = *env.step_counter().last_foot();
    const int body = foot == Foot::left ? env.bodies().left_foot : env.bodies().right_foot;
    tr.touchdowns.push_back({t, env.world().body_centroid(body).x(), foot, tr.t_s.size() - 1});
  }
  tr.steps = steps;
}

// The episode's figures from its trace (outcome, draw and times set by the caller).
void measure(const Trace& tr, const RaceSettings& s, double length_m, RaceEpisode& e) {
  if (tr.t_s.empty()) return;
  e.distance_m = tr.root_x.back() - tr.root_x.front();
  e.splits_s = split_times(tr.t_s, tr.front_x, s.split_m, length_m, e.finish_time_s);
  e.speed_profile_mps = speed_profile(tr.t_s, tr.root_x, s.profile_bin_m, length_m);
  e.top_speed = top_speed(tr.t_s, tr.root_x, s.top_speed_window_m, s.profile_bin_m);
  e.steps = tr.steps;
  double length = 0.0, time = 0.0;
  for (std::size_t i = 1; i < tr.touchdowns.size(); ++i)
    length += tr.touchdowns[i].x_m - tr.touchdowns[i - 1].x_m, time += tr.touchdowns[i].t_s - tr.touchdowns[i - 1].t_s;
  if (tr.touchdowns.size() > 1) {
    e.step_length_m = length / static_cast<double>(tr.touchdowns.size() - 1);
    e.step_frequency_hz = time > 0.0 ? static_cast<double>(tr.touchdowns.size() - 1) / time : 0.0;
  }
  e.segments = steps_by_segment(tr.touchdowns, s.split_m, length_m);
  e.lean_per_step_rad = lean_per_step(tr.touchdowns, tr.lean);
  std::vector<double> first;
  for (std::size_t i = 0; i < tr.root_x.size(); ++i)
    if (tr.root_x[i] >= 0.0 && tr.root_x[i] < std::min(s.split_m, length_m)) first.push_back(tr.lean[i]);
  e.first_segment_lean_rad = mean_of(first);
  e.rise_distance_m = rise_distance(tr.root_x, tr.lean, s.rise_lean_deg / kDeg);
  e.asymmetry = step_asymmetry(tr.touchdowns);
}

void check_fits(const learn::FrozenPolicy& policy, const SprintEnv& env, const std::string& who) {
  if (policy.observation_size() == env.observation_space().size() && policy.action_size() == env.action_space().size()) return;
  throw base::UserError("sprint race: the " + who + " policy takes " + std::to_string(policy.observation_size()) +
                        " observations and gives " + std::to_string(policy.action_size()) + " actions; its environment has " +
                        std::to_string(env.observation_space().size()) + " and " + std::to_string(env.action_space().size()) +
                        " (a policy of another stage or track?)");
}

// What every episode shares: the two phases' environment settings and policies.
struct RaceContext {
  const RaceSettings& s;
  double length_m = 0.0;
  SprintEnvSettings start, accelerate;
  const RacePolicyFns& policies;
};

// Steps `env` with `policy` to the episode's end, sampling (and recording) after every step;
// `before` may change each action (the dip).
void run_phase(SprintEnv& env, const character::PolicyFn& policy, std::vector<double>& observation, Trace& tr,
               sim::Recorder* recorder, const std::function<void(std::span<double>)>& before = {}) {
  std::vector<double> action(env.action_space().size());
  learn::StepResult step;
  for (;;) {
    policy(observation, action);
    if (before) before(action);
    env.step(action, step);
    if (recorder) recorder->record(env.world());
    take_sample(env, tr);
    if (step.terminated || step.truncated) return;
    observation.swap(step.observation);
  }
}

// One race: the Start phase from the blocks to the first landing, then stage 2 from that
// landing's hand-over state (its World, draw and step count) with the dip, to the end.
RaceEpisode run_episode(const RaceContext& c, int index, std::uint64_t seed, const EpisodeDraw& draw, sim::Recorder* recorder,
                        const std::optional<DipParams>& dip) {
  RaceEpisode e;
  e.index = index, e.seed = seed, e.draw = draw;
  Trace tr;
  std::vector<double> observation;
  SprintEnvSettings start_settings = c.start;
  start_settings.fixed_draw = draw;
  SprintEnv start(start_settings);
  start.seed(seed);
  start.reset(observation);
  if (recorder) recorder->record(start.world());
  take_sample(start, tr);
  run_phase(start, c.policies.start, observation, tr, recorder);
  e.reference = c.start.start_references.at(static_cast<std::size_t>(start.reference_index())).name;
  if (start.outcome() != SprintEnv::Outcome::landed || !start.landing_state()) {
    e.outcome = start.outcome() == SprintEnv::Outcome::running ? "no_landing" : to_string(start.outcome());
    measure(tr, c.s, c.length_m, e);
    return e;
  }
  e.landing_time_s = start.world().time_s();
  SprintEnvSettings settings = c.accelerate;
  settings.fixed_draw = draw;
  settings.handover_states = {*start.landing_state()};
  SprintEnv run(settings);
  run.seed(base::derive_seed(seed, 1));
  run.reset(observation);                 // the landing's state, already sampled and recorded
  std::optional<DipActions> dip_actions;  // the dip stage's change of targets and firing rule (dip.h)
  std::optional<DipTrigger> trigger;
  if (dip) dip_actions.emplace(run.world().model_ptr(), false), trigger.emplace(*dip, *dip_actions, c.length_m);
  int step = 0;
  run_phase(run, c.policies.accelerate, observation, tr, recorder, [&](std::span<double> action) {
    if (trigger) trigger->apply(step++, run.world().data().q(0), action);
  });
  if (trigger && trigger->fired_step() >= 0) e.dip_x_m = trigger->fired_x_m();
  e.outcome = run.outcome() == SprintEnv::Outcome::running ? "time_limit" : to_string(run.outcome());
  if (run.outcome() == SprintEnv::Outcome::finished) e.finish_time_s = run.finish_line().finish_time();
  measure(tr, c.s, c.length_m, e);
  return e;
}

// The lane and the lines, drawn in the replay only (not in the World: no contact changes): thin
// boxes of kind "line" on the ground, 5 cm wide; as athletics measures the race from the start
// line's edge farther from the finish to the finish line's nearer edge, the start line lies on
// [0, w] (the hands stay behind it) and the finish line on [L, L + w].
void add_track_lines(const fs::path& file, const TrackSpec& track) {
  std::ifstream in(file);
  std::string header, rest, line;
  std::getline(in, header);
  while (std::getline(in, line)) rest += line + '\n';
  in.close();
  Json h = Json::parse(header);
  const double w = 0.05, z = 0.001, half_lane = 0.5 * track.lane_width_m, y0 = track.lane_centre_y_m;
  const auto box = [&](const std::string& name, double x, double y, double hx, double hy) {
    return Json{{"name", name},     {"type", "box"},        {"kind", "line"},
                {"pos", {x, y, z}}, {"quat", {1, 0, 0, 0}}, {"half_extents", {hx, hy, z}},
                {"friction", 0.0}};
  };
  const double lane_from = -2.0, lane_to = track.length_m + 5.0;
  h["props"].push_back(box("start_line", 0.5 * w, y0, 0.5 * w, half_lane));
  h["props"].push_back(box("finish_line", track.length_m + 0.5 * w, y0, 0.5 * w, half_lane));
  for (const int side : {-1, 1})
    h["props"].push_back(box(side < 0 ? "lane_right" : "lane_left", 0.5 * (lane_from + lane_to),
                             y0 + side * (half_lane + 0.5 * w), 0.5 * (lane_to - lane_from), 0.5 * w));
  // A new file renamed over the old: a trial killed mid-write leaves the recorder's whole file.
  fs::path tmp = file;
  tmp += ".lines";
  {
    std::ofstream out(tmp);
    out << h.dump() << '\n' << rest;
    if (!out.flush()) throw base::UserError(tmp.string() + ": cannot write the race motion");
  }
  fs::rename(tmp, file);
}

}  // namespace

namespace {

// Mean and count over the episodes that have a value.
struct Tally {
  std::vector<double> values;
  void add(const std::optional<double>& v) {
    if (v) values.push_back(*v);
  }
  Json mean() const { return values.empty() ? Json(nullptr) : Json(mean_of(values)); }
};

Json wind_check_json(const std::vector<RaceEpisode>& head, const std::vector<RaceEpisode>& tail) {
  std::vector<double> h, t, d;
  int slower = 0, head_finished = 0, tail_finished = 0;
  for (std::size_t i = 0; i < head.size() && i < tail.size(); ++i) {
    head_finished += head[i].finish_time_s ? 1 : 0, tail_finished += tail[i].finish_time_s ? 1 : 0;
    if (!head[i].finish_time_s || !tail[i].finish_time_s) continue;
    h.push_back(*head[i].finish_time_s), t.push_back(*tail[i].finish_time_s), d.push_back(h.back() - t.back());
    slower += d.back() > 0.0 ? 1 : 0;
  }
  const auto n = static_cast<double>(std::max<std::size_t>(1, head.size()));
  return {{"episodes", head.size()},
          {"headwind_finish_rate", head_finished / n},
          {"tailwind_finish_rate", tail_finished / n},
          {"pairs", d.size()},
          {"headwind_mean_finish_time_s", d.empty() ? Json(nullptr) : Json(mean_of(h))},
          {"tailwind_mean_finish_time_s", d.empty() ? Json(nullptr) : Json(mean_of(t))},
          {"mean_difference_s", d.empty() ? Json(nullptr) : Json(mean_of(d))},
          {"headwind_slower", slower}};
}

// The dip check (§3.3's gain, on the race's held-out episodes): each episode with the dip against
// the same episode without it. The gain is the no-dip time minus the dip time, over the pairs that
// finish both ways; an added fall is an episode that finishes without the dip and not with it.
Json dip_check_json(const std::vector<RaceEpisode>& none, const std::vector<RaceEpisode>& dip) {
  std::vector<double> gain;
  int improved = 0, added_falls = 0, fired = 0, none_finished = 0;
  for (std::size_t i = 0; i < none.size() && i < dip.size(); ++i) {
    none_finished += none[i].finish_time_s ? 1 : 0, fired += dip[i].dip_x_m ? 1 : 0;
    if (none[i].finish_time_s && !dip[i].finish_time_s) ++added_falls;
    if (!none[i].finish_time_s || !dip[i].finish_time_s) continue;
    gain.push_back(*none[i].finish_time_s - *dip[i].finish_time_s);
    improved += gain.back() > 0.0 ? 1 : 0;
  }
  const auto n = static_cast<double>(std::max<std::size_t>(1, none.size()));
  const bool paired = gain.size() > 1;
  return {{"episodes", none.size()},
          {"no_dip_finish_rate", none_finished / n},
          {"fired_rate", fired / n},
          {"pairs", gain.size()},
          {"mean_gain_s", gain.empty() ? Json(nullptr) : Json(mean_of(gain))},
          {"gain_standard_error_s", paired ? Json(std_of(gain) / std::sqrt(static_cast<double>(gain.size()))) : Json(nullptr)},
          {"improved", improved},
          {"added_falls", added_falls}};
}

std::string fixed(const std::optional<double>& v, int decimals = 2) {
  if (!v) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", decimals, *v);
  return b;
}

}  // namespace

Json RaceReport::summary() const {
  const auto n = static_cast<double>(std::max<std::size_t>(1, episodes.size()));
  std::vector<double> finish, race, steps;
  Tally top, top_at, length, frequency, rise, lean, length_index, time_index;
  std::vector<Tally> splits, seg_length, seg_frequency;
  Json outcomes = Json::object();
  for (const RaceEpisode& e : episodes) {
    outcomes[e.outcome] = outcomes.value(e.outcome, 0) + 1;
    race.push_back(e.finish_time_s.value_or(time_limit_s));
    if (e.finish_time_s) {
      finish.push_back(*e.finish_time_s), steps.push_back(e.steps);
      if (splits.size() < e.splits_s.size()) splits.resize(e.splits_s.size());
      for (std::size_t k = 0; k < e.splits_s.size(); ++k) splits[k].add(e.splits_s[k]);
    }
    if (e.top_speed) top.add(e.top_speed->speed_mps), top_at.add(e.top_speed->at_m);
    if (e.step_length_m > 0.0) length.add(e.step_length_m), frequency.add(e.step_frequency_hz);
    rise.add(e.rise_distance_m);
    lean.add(e.first_segment_lean_rad * kDeg);
    if (e.asymmetry.left_steps > 0 && e.asymmetry.right_steps > 0)
      length_index.add(e.asymmetry.length_index), time_index.add(e.asymmetry.time_index);
    if (seg_length.size() < e.segments.size()) seg_length.resize(e.segments.size()), seg_frequency.resize(e.segments.size());
    for (std::size_t k = 0; k < e.segments.size(); ++k)
      if (e.segments[k].steps > 0) seg_length[k].add(e.segments[k].length_m), seg_frequency[k].add(e.segments[k].frequency_hz);
  }
  Json split_means = Json::array(), segments = Json::array();
  for (const Tally& t : splits) split_means.push_back(t.mean());
  for (std::size_t k = 0; k < seg_length.size(); ++k)
    segments.push_back({{"from_m", static_cast<double>(k) * settings.split_m},
                        {"to_m", std::min(static_cast<double>(k + 1) * settings.split_m, length_m)},
                        {"step_length_m", seg_length[k].mean()},
                        {"step_frequency_hz", seg_frequency[k].mean()}});
  return {{"episodes", episodes.size()},
          {"finishers", finish.size()},
          {"finish_rate", static_cast<double>(finish.size()) / n},
          {"outcomes", outcomes},
          {"mean_finish_time_s", finish.empty() ? Json(nullptr) : Json(mean_of(finish))},
          {"std_finish_time_s", finish.empty() ? Json(nullptr) : Json(std_of(finish))},
          {"best_finish_time_s", finish.empty() ? Json(nullptr) : Json(*std::min_element(finish.begin(), finish.end()))},
          {"mean_race_time_s", mean_of(race)},
          {"time_limit_s", time_limit_s},
          {"mean_splits_s", split_means},
          {"mean_top_speed_mps", top.mean()},
          {"mean_top_speed_at_m", top_at.mean()},
          {"mean_steps", finish.empty() ? Json(nullptr) : Json(mean_of(steps))},
          {"std_steps", finish.empty() ? Json(nullptr) : Json(std_of(steps))},
          {"mean_step_length_m", length.mean()},
          {"mean_step_frequency_hz", frequency.mean()},
          {"segments", segments},
          {"mean_rise_distance_m", rise.mean()},
          {"rise_rate", static_cast<double>(rise.values.size()) / n},
          {"mean_first_segment_lean_deg", lean.mean()},
          {"mean_step_length_asymmetry", length_index.mean()},
          {"mean_step_time_asymmetry", time_index.mean()},
          {"dip",
           settings.dip ? Json{{"distance_m", settings.dip->distance_m}, {"angle_deg", settings.dip->angle_deg}} : Json(nullptr)},
          {"dip_check", settings.dip ? dip_check_json(no_dip, episodes) : Json(nullptr)},
          {"wind_check", settings.wind_check ? wind_check_json(headwind, tailwind) : Json(nullptr)}};
}

Json RaceReport::to_json() const {
  Json all = Json::array(), head = Json::array(), tail = Json::array(), none = Json::array();
  for (const RaceEpisode& e : episodes) all.push_back(e.to_json());
  for (const RaceEpisode& e : no_dip) none.push_back(e.to_json());
  for (const RaceEpisode& e : headwind) head.push_back(e.to_json());
  for (const RaceEpisode& e : tailwind) tail.push_back(e.to_json());
  return {{"track_m", length_m},
          {"settings",
           {{"track", settings.track},
            {"sim_hz", settings.sim_hz},
            {"seed", settings.seed},
            {"split_m", settings.split_m},
            {"profile_bin_m", settings.profile_bin_m},
            {"top_speed_window_m", settings.top_speed_window_m},
            {"rise_lean_deg", settings.rise_lean_deg},
            {"wind_check_mps", settings.wind_check ? Json(settings.wind_check_mps) : Json(nullptr)}}},
          {"summary", summary()},
          {"episodes", all},
          {"headwind", head},
          {"tailwind", tail},
          {"no_dip", none}};
}

Json RaceReport::result_table() const {
  const Json columns = {column("episode"),
                        column("wind", "m/s"),
                        column("μ"),
                        column("outcome"),
                        column("finish time", "s"),
                        column("top speed", "m/s"),
                        column("top speed at", "m"),
                        column("steps"),
                        column("step length", "m"),
                        column("step frequency", "Hz"),
                        column("rise distance", "m")};
  Json rows = Json::array();
  for (const RaceEpisode& e : episodes)
    rows.push_back({e.index, e.draw.wind_mps, e.draw.friction, e.outcome, optional_json(e.finish_time_s),
                    e.top_speed ? Json(e.top_speed->speed_mps) : Json(nullptr),
                    e.top_speed ? Json(e.top_speed->at_m) : Json(nullptr), e.steps,
                    e.steps > 1 ? Json(e.step_length_m) : Json(nullptr), e.steps > 1 ? Json(e.step_frequency_hz) : Json(nullptr),
                    optional_json(e.rise_distance_m)});
  return {{"title", "race over " + fixed(length_m, 0) + " m"}, {"columns", columns}, {"rows", rows}};
}

namespace {

void text_dip_check(std::ostringstream& o, const Json& d) {
  const auto v = [&](const char* key) { return d[key].is_null() ? std::string("-") : fixed(d[key].get<double>(), 3); };
  o << "\ndip check, paired (each episode without the dip): pairs " << d["pairs"].get<int>() << ", gain (no dip − dip) "
    << v("mean_gain_s") << " s ± " << v("gain_standard_error_s") << " (s.e.), faster in " << d["improved"].get<int>()
    << ", falls added " << d["added_falls"].get<int>() << ", finish rate without the dip " << v("no_dip_finish_rate")
    << ", fired in " << v("fired_rate") << " of the episodes\n";
}

}  // namespace

std::string RaceReport::text_table() const {
  std::ostringstream o;
  char line[512];
  const Json s = summary();
  std::snprintf(
      line, sizeof line, "Race over %.0f m: %zu DR episodes (seed %llu), dip %s\n", length_m, episodes.size(),
      static_cast<unsigned long long>(settings.seed),
      settings.dip ? (fixed(settings.dip->distance_m) + " m, " + fixed(settings.dip->angle_deg, 1) + " deg").c_str() : "none");
  o << line;
  o << "  #  wind   mu    reference                 outcome     time s  top m/s  at m  steps  len m  freq Hz  rise m  lean0 deg"
       "  asym len/time  splits s\n";
  for (const RaceEpisode& e : episodes) {
    std::string splits;
    for (const double t : e.splits_s) splits += (splits.empty() ? "" : " ") + fixed(t);
    const auto per_step = [&](double v) { return e.steps > 1 ? std::optional(v) : std::nullopt; };
    std::snprintf(
        line, sizeof line, "%3d  %+5.2f  %4.2f  %-24s  %-10s  %6s  %7s  %4s  %5d  %5s  %7s  %6s  %9.1f  %5s/%-5s  %s\n", e.index,
        e.draw.wind_mps, e.draw.friction, e.reference.c_str(), e.outcome.c_str(), fixed(e.finish_time_s).c_str(),
        fixed(e.top_speed ? std::optional(e.top_speed->speed_mps) : std::nullopt).c_str(),
        fixed(e.top_speed ? std::optional(e.top_speed->at_m) : std::nullopt, 1).c_str(), e.steps,
        fixed(per_step(e.step_length_m)).c_str(), fixed(per_step(e.step_frequency_hz)).c_str(),
        fixed(e.rise_distance_m, 1).c_str(), e.first_segment_lean_rad * kDeg,
        fixed(e.asymmetry.left_steps > 0 && e.asymmetry.right_steps > 0 ? std::optional(e.asymmetry.length_index) : std::nullopt)
            .c_str(),
        fixed(e.asymmetry.left_steps > 0 && e.asymmetry.right_steps > 0 ? std::optional(e.asymmetry.time_index) : std::nullopt)
            .c_str(),
        splits.c_str());
    o << line;
  }
  const auto value = [&](const char* key, int decimals = 2) {
    return s[key].is_null() ? std::string("-") : fixed(s[key].get<double>(), decimals);
  };
  o << "\nfinish rate " << value("finish_rate") << "; finish time mean " << value("mean_finish_time_s") << " s, sd "
    << value("std_finish_time_s") << " s, best " << value("best_finish_time_s") << " s; race time (a DNF at "
    << fixed(time_limit_s) << " s) " << value("mean_race_time_s") << " s\n";
  o << "top speed " << value("mean_top_speed_mps") << " m/s at " << value("mean_top_speed_at_m", 1) << " m; steps "
    << value("mean_steps", 1) << " (sd " << value("std_steps", 1) << "); step length " << value("mean_step_length_m")
    << " m, frequency " << value("mean_step_frequency_hz") << " Hz; rise distance " << value("mean_rise_distance_m", 1)
    << " m (rate " << value("rise_rate") << "); lean over the first segment " << value("mean_first_segment_lean_deg", 1)
    << " deg; asymmetry length " << value("mean_step_length_asymmetry") << ", time " << value("mean_step_time_asymmetry") << "\n";
  o << "per segment (m: step length m, frequency Hz):";
  for (const Json& g : s["segments"])
    o << "  " << fixed(g["from_m"].get<double>(), 0) << "-" << fixed(g["to_m"].get<double>(), 0) << ": "
      << (g["step_length_m"].is_null() ? "-" : fixed(g["step_length_m"].get<double>())) << ", "
      << (g["step_frequency_hz"].is_null() ? "-" : fixed(g["step_frequency_hz"].get<double>()));
  o << "\n";
  if (settings.dip) text_dip_check(o, s["dip_check"]);
  if (!settings.wind_check) return o.str();
  const Json& w = s["wind_check"];
  const auto wv = [&](const char* key) { return w[key].is_null() ? std::string("-") : fixed(w[key].get<double>(), 3); };
  o << "\nwind check, paired (the same episodes, μ as drawn): wind " << fixed(-settings.wind_check_mps, 1) << " vs "
    << fixed(settings.wind_check_mps, 1) << " m/s\n  #  headwind s  tailwind s  difference s\n";
  for (std::size_t i = 0; i < headwind.size() && i < tailwind.size(); ++i) {
    const auto& h = headwind[i].finish_time_s;
    const auto& t = tailwind[i].finish_time_s;
    std::snprintf(line, sizeof line, "%3zu  %10s  %10s  %12s\n", i, fixed(h, 3).c_str(), fixed(t, 3).c_str(),
                  fixed(h && t ? std::optional(*h - *t) : std::nullopt, 3).c_str());
    o << line;
  }
  o << "pairs " << w["pairs"].get<int>() << ", headwind mean " << wv("headwind_mean_finish_time_s") << " s, tailwind mean "
    << wv("tailwind_mean_finish_time_s") << " s, difference " << wv("mean_difference_s") << " s, headwind slower in "
    << w["headwind_slower"].get<int>() << "\n";
  return o.str();
}

RaceEnvSettings race_env_settings(const RaceSettings& settings) {
  const SprintPreset preset = load_sprint_preset(settings.track);
  RaceEnvSettings e;
  e.accelerate.preset = preset;
  e.accelerate.sim_hz = settings.sim_hz;
  e.start = e.accelerate;
  e.start.start_references =
      start_references(sim::load_shipped_model(e.start.model), e.start.control_hz, preset.start, settings.start_clips);
  // The race runs the Start policy to its landing: no early termination on a deviation from the
  // reference (a training device), only the sprint's falls, the lane and the Start's time limit.
  e.start.preset.start.max_com_deviation_m = std::numeric_limits<double>::infinity();
  e.start.preset.start.min_pose_reward = 0.0;
  return e;
}

RaceReport run_race(const RaceSettings& settings, const RacePolicies& policies, const fs::path& work_dir,
                    const std::atomic<bool>* cancel, const std::function<void(double)>& progress) {
  const auto start = std::make_shared<const learn::FrozenPolicy>(policies.start);
  const auto accelerate = std::make_shared<const learn::FrozenPolicy>(policies.accelerate);
  {
    const RaceEnvSettings e = race_env_settings(settings);
    check_fits(*start, SprintEnv(e.start), "start");
    check_fits(*accelerate, SprintEnv(e.accelerate), "accelerate");  // stage 2's observation, whatever its start
  }
  const RacePolicyFns fns{[start](std::span<const double> o, std::span<double> a) { start->act(o, a); },
                          [accelerate](std::span<const double> o, std::span<double> a) { accelerate->act(o, a); }};
  return run_race(settings, fns, work_dir, cancel, progress);
}

RaceReport run_race(const RaceSettings& settings, const RacePolicyFns& policies, const fs::path& work_dir,
                    const std::atomic<bool>* cancel, const std::function<void(double)>& progress) {
  const SprintPreset preset = load_sprint_preset(settings.track);
  const RaceEnvSettings envs = race_env_settings(settings);
  const RaceContext c{settings, preset.track.length_m, envs.start, envs.accelerate, policies};
  RaceReport report;
  report.settings = settings;
  report.length_m = preset.track.length_m;
  {
    const SprintEnv start(c.start), run(c.accelerate);
    report.time_limit_s = (start.episode_steps() + run.episode_steps()) * start.control_dt_s();
  }
  const int n = settings.episodes > 0 ? settings.episodes : preset.race.episodes;
  const int per_episode = 1 + (settings.wind_check ? 2 : 0) + (settings.dip ? 1 : 0), runs = per_episode * n;
  const fs::path motions = work_dir / "rollouts" / "race";
  for (int k = 0; k < n; ++k) {
    if (cancel && cancel->load()) throw std::runtime_error("sprint race: cancelled");
    const std::uint64_t seed = base::derive_seed(settings.seed, static_cast<std::uint64_t>(k));
    base::Rng rng(base::derive_seed(settings.seed, static_cast<std::uint64_t>(k), 1));
    const EpisodeDraw draw = draw_episode(preset, rng);
    std::optional<sim::Recorder> recorder;
    if (k < settings.record) recorder.emplace(sim::load_shipped_model(c.start.model));
    report.episodes.push_back(run_episode(c, k, seed, draw, recorder ? &*recorder : nullptr, settings.dip));
    if (recorder) {
      fs::create_directories(motions);
      const fs::path file = motions / ("trajectory_" + std::to_string(k) + ".jsonl");
      sim::write_trajectory(*recorder, file);
      add_track_lines(file, preset.track);
      report.motions.push_back(file);
    }
    if (settings.wind_check) {  // the same episode (seed, reference, μ) in a headwind, then a tailwind
      report.headwind.push_back(run_episode(c, k, seed, {-settings.wind_check_mps, draw.friction}, nullptr, settings.dip));
      report.tailwind.push_back(run_episode(c, k, seed, {settings.wind_check_mps, draw.friction}, nullptr, settings.dip));
    }
    if (settings.dip) report.no_dip.push_back(run_episode(c, k, seed, draw, nullptr, std::nullopt));  // the dip check
    if (progress) progress(static_cast<double>(per_episode * (k + 1)) / runs);
  }
  return report;
}

}  // namespace podium::tasks::sprint
