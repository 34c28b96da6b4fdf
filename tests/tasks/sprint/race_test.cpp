// The race report (tasks/sprint/race.h): splits, step statistics, lean, speed profile and top
// speed on scripted sequences; the dip's hip flexion on humanoid34; and a whole race in-process
// with untrained policies (what it records, determinism, the wind check's pairing).
#include "race.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <numeric>
#include <set>
#include <vector>

#include "crouch_start.h"
#include "dip.h"
#include "podium/base/json.h"
#include "podium/character/pose_bridge.h"
#include "podium/learn/learner.h"
#include "podium/sim/dynamics.h"
#include "process.h"
#include "shared_data.h"
#include "sprint_env.h"
#include "sprint_rewards.h"

namespace podium::tasks::sprint {
namespace {

using base::Json;
namespace fs = std::filesystem;

// Samples every dt of x(t) = x0 + v·t + a·t²/2.
void scripted_run(double x0, double v, double a, double dt, double t_end, std::vector<double>& t, std::vector<double>& x) {
  for (double s = 0.0; s <= t_end + 1e-12; s += dt) t.push_back(s), x.push_back(x0 + v * s + 0.5 * a * s * s);
}

TEST(SprintRace, SplitsAreTheMarksCrossingTimesThenTheFinish) {
  std::vector<double> t, x;
  scripted_run(-0.5, 4.0, 0.0, 1.0 / 30.0, 8.0, t, x);  // 4 m/s from 0.5 m behind the line
  const std::vector<double> splits = split_times(t, x, 10.0, 30.0, 7.625);
  ASSERT_EQ(splits.size(), 3u);
  EXPECT_NEAR(splits[0], 10.5 / 4.0, 1e-12);
  EXPECT_NEAR(splits[1], 20.5 / 4.0, 1e-12);
  EXPECT_EQ(splits[2], 7.625);  // the finish time as given (the finish line's, within the sim step)
  // A run that stops short: the marks it reached only, no finish.
  std::vector<double> t2, x2;
  scripted_run(0.0, 4.0, 0.0, 0.1, 3.0, t2, x2);
  EXPECT_EQ(split_times(t2, x2, 10.0, 30.0, std::nullopt).size(), 1u);
  // Two marks inside one sampling interval: each interpolated.
  const std::vector<double> coarse = split_times({0.0, 1.0}, {0.0, 25.0}, 10.0, 30.0, std::nullopt);
  ASSERT_EQ(coarse.size(), 2u);
  EXPECT_NEAR(coarse[0], 0.4, 1e-12);
  EXPECT_NEAR(coarse[1], 0.8, 1e-12);
  EXPECT_THROW(split_times({0.0}, {0.0, 1.0}, 10.0, 30.0, std::nullopt), base::UserError);
}

// Alternating touchdowns: left steps 1.0 m in 0.25 s, right steps 1.2 m in 0.3 s, from x = 0.5.
std::vector<Touchdown> scripted_steps(int n) {
  std::vector<Touchdown> td;
  double t = 0.4, x = 0.5;
  for (int i = 0; i < n; ++i) {
    const Foot foot = i % 2 == 0 ? Foot::right : Foot::left;
    if (i > 0) t += foot == Foot::left ? 0.25 : 0.3, x += foot == Foot::left ? 1.0 : 1.2;
    td.push_back({t, x, foot, static_cast<std::size_t>(3 * i + 2)});
  }
  return td;
}

TEST(SprintRace, StepLengthAndFrequencyPerSegmentFromAlternatingTouchdowns) {
  const std::vector<Touchdown> td = scripted_steps(10);  // last touchdown at 0.5 + 4.5·1.0 + 4·1.2... ≈ 10.3 m
  const std::vector<SegmentSteps> seg = steps_by_segment(td, 5.0, 10.0);
  ASSERT_EQ(seg.size(), 2u);
  // Steps 1–9 land at 1.5, 2.7, 3.7, 4.9 | 5.9, 7.1, 8.1, 9.3 | 10.3 (past the line: not counted).
  EXPECT_EQ(seg[0].steps, 4);
  EXPECT_EQ(seg[1].steps, 4);
  EXPECT_NEAR(seg[0].length_m, 1.1, 1e-12);
  EXPECT_NEAR(seg[0].frequency_hz, 4.0 / 1.1, 1e-12);  // 2 × 0.25 s + 2 × 0.3 s
  EXPECT_NEAR(seg[1].length_m, 1.1, 1e-12);
  EXPECT_EQ(seg[1].from_m, 5.0);
  EXPECT_EQ(seg[1].to_m, 10.0);
  // A segment without steps stays empty; the last segment is shorter when it does not divide.
  const std::vector<SegmentSteps> wide = steps_by_segment(td, 4.0, 10.0);
  ASSERT_EQ(wide.size(), 3u);
  EXPECT_EQ(wide[2].to_m, 10.0);
  EXPECT_EQ(steps_by_segment({}, 10.0, 30.0)[1].steps, 0);
}

TEST(SprintRace, AsymmetryComparesLeftAndRightSteps) {
  const StepAsymmetry a = step_asymmetry(scripted_steps(9));
  EXPECT_EQ(a.left_steps, 4);
  EXPECT_EQ(a.right_steps, 4);
  EXPECT_NEAR(a.left_length_m, 1.0, 1e-12);
  EXPECT_NEAR(a.right_length_m, 1.2, 1e-12);
  EXPECT_NEAR(a.length_index, 0.2 / 1.1, 1e-12);
  EXPECT_NEAR(a.left_time_s, 0.25, 1e-12);
  EXPECT_NEAR(a.right_time_s, 0.3, 1e-12);
  EXPECT_NEAR(a.time_index, 0.05 / 0.275, 1e-12);
  // Symmetric steps: 0; one side only: no index.
  std::vector<Touchdown> even = {{0.0, 0.0, Foot::left, 0}, {0.3, 1.0, Foot::right, 1}, {0.6, 2.0, Foot::left, 2}};
  EXPECT_EQ(step_asymmetry(even).length_index, 0.0);
  EXPECT_EQ(step_asymmetry(even).time_index, 0.0);
  even.pop_back();
  EXPECT_EQ(step_asymmetry(even).length_index, 0.0);
  EXPECT_EQ(step_asymmetry(even).right_steps, 1);
}

TEST(SprintRace, LeanPerStepIsTheMeanFromEachTouchdownToTheNext) {
  const std::vector<double> lean = {0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3};
  const std::vector<Touchdown> td = {{0.0, 0.0, Foot::left, 1}, {0.0, 0.0, Foot::right, 4}};
  const std::vector<double> per = lean_per_step(td, lean);
  ASSERT_EQ(per.size(), 2u);
  EXPECT_NEAR(per[0], (0.8 + 0.7 + 0.6) / 3.0, 1e-12);
  EXPECT_NEAR(per[1], (0.5 + 0.4 + 0.3) / 3.0, 1e-12);
  EXPECT_THROW(lean_per_step({{0.0, 0.0, Foot::left, 7}}, lean), base::UserError);
}

TEST(SprintRace, SpeedProfileAndTopSpeedOfAnAcceleratingThenSteadyRun) {
  // 2 m/s² from rest to 8 m/s at x = 16 m (t = 4 s), then steady.
  std::vector<double> t, x;
  for (double s = 0.0; s <= 6.0 + 1e-12; s += 0.01) {
    t.push_back(s);
    x.push_back(s <= 4.0 ? s * s : 16.0 + 8.0 * (s - 4.0));
  }
  const auto profile = speed_profile(t, x, 4.0, 36.0);
  ASSERT_EQ(profile.size(), 9u);
  EXPECT_NEAR(*profile[0], 4.0 / 2.0, 1e-3);  // 0–4 m in 2 s
  EXPECT_NEAR(*profile[5], 8.0, 1e-9);        // steady
  EXPECT_FALSE(profile[8].has_value());       // 32–36 m: never reached
  const auto top = top_speed(t, x, 4.0, 1.0);
  ASSERT_TRUE(top.has_value());
  EXPECT_NEAR(top->speed_mps, 8.0, 1e-9);
  EXPECT_GE(top->at_m, 18.0);  // the first whole window in the steady part
  EXPECT_NEAR(top->at_m, 18.0, 1e-9);
  EXPECT_FALSE(top_speed(t, x, 50.0, 1.0).has_value());
}

TEST(SprintRace, TheDipFlexesBothHipsByItsAngle) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const character::PoseBridge bridge(model);
  std::vector<double> action(bridge.size(), 0.0);
  const std::vector<double> untouched = action;
  const DipActions dip(model, false);
  dip.apply(0.0, action);
  EXPECT_EQ(action, untouched);  // θ = 0: bitwise the policy's action
  const double theta = 30.0 * std::numbers::pi / 180.0;
  dip.apply(theta, action);
  sim::CharacterData d(*model);
  d.q = model->standing_pose();
  bridge.set_pose(action, d.q);
  sim::forward_kinematics(*model, d);
  const SprintBodies b = SprintBodies::of(*model);
  EXPECT_NEAR(sagittal_angle(*model, d, b.left_thigh), theta, 1e-9);  // the knee forward by θ
  EXPECT_NEAR(sagittal_angle(*model, d, b.right_thigh), theta, 1e-9);
  // On top of a pose already flexed: the angles add in the sagittal plane.
  std::vector<double> flexed(bridge.size(), 0.0);
  dip.apply(0.2, flexed);
  dip.apply(theta, flexed);
  bridge.set_pose(flexed, d.q);
  sim::forward_kinematics(*model, d);
  EXPECT_NEAR(sagittal_angle(*model, d, b.left_thigh), 0.2 + theta, 1e-9);
}

// An untrained policy of the right shape for `env`, written as a TorchScript file.
fs::path untrained_policy(const SprintEnv& env, const fs::path& file, std::uint64_t seed) {
  const auto learner = learn::make_learner({{"algorithm", "ppo"}, {"preset", "quick"}, {"config", {{"hidden", {8, 8}}}}},
                                           env.observation_space(), env.action_space(), seed);
  learner->export_torchscript(file);
  return file;
}

TEST(SprintRace, ARaceRecordsEveryEpisodeItsDrawAndAPairedWindCheck) {
  podium::testing::TempDir dir;
  SprintEnvSettings s;
  s.preset = load_sprint_preset("smoke");
  s.sim_hz = 150.0;
  const SprintEnv run(s);
  s.start_references = crouch_start_references(sim::load_shipped_model(s.model), s.control_hz, s.preset.start);
  const SprintEnv start(s);
  const RacePolicies policies{untrained_policy(start, dir.path() / "start.pt", 1),
                              untrained_policy(run, dir.path() / "run.pt", 2)};
  RaceSettings settings;
  settings.sim_hz = 150.0;
  settings.episodes = 3;
  settings.record = 1;
  std::vector<double> progress;
  const RaceReport a = run_race(settings, policies, dir.path() / "a", nullptr, [&](double f) { progress.push_back(f); });
  ASSERT_EQ(a.episodes.size(), 3u);
  ASSERT_EQ(a.headwind.size(), 3u);
  ASSERT_EQ(a.tailwind.size(), 3u);
  EXPECT_EQ(progress.back(), 1.0);
  EXPECT_EQ(a.length_m, 10.0);
  EXPECT_GT(a.time_limit_s, 0.0);
  for (std::size_t k = 0; k < 3; ++k) {
    const RaceEpisode& e = a.episodes[k];
    EXPECT_GE(e.draw.wind_mps, -2.0);
    EXPECT_LE(e.draw.wind_mps, 2.0);
    EXPECT_GE(e.draw.friction, 0.8);
    EXPECT_LE(e.draw.friction, 1.2);
    EXPECT_FALSE(e.reference.empty());
    EXPECT_FALSE(e.outcome.empty());
    EXPECT_EQ(e.finish_time_s.has_value(), e.outcome == "finished");
    // The wind check: the same episode (reference, μ), only the wind set.
    EXPECT_EQ(a.headwind[k].reference, e.reference);
    EXPECT_EQ(a.headwind[k].draw.friction, e.draw.friction);
    EXPECT_EQ(a.headwind[k].draw.wind_mps, -2.0);
    EXPECT_EQ(a.tailwind[k].draw.wind_mps, 2.0);
  }
  EXPECT_NE(a.episodes[0].draw.friction, a.episodes[1].draw.friction);  // a draw per episode
  // Deterministic: the same settings give the same figures.
  RaceSettings quiet = settings;
  quiet.record = 0;
  const RaceReport b = run_race(quiet, policies, dir.path() / "b");
  EXPECT_EQ(a.summary(), b.summary());
  EXPECT_EQ(a.episodes[2].to_json(), b.episodes[2].to_json());
  EXPECT_TRUE(b.motions.empty());
  // The motion: a trajectory file whose header carries the blocks and the drawn lines.
  ASSERT_EQ(a.motions.size(), 1u);
  std::ifstream in(a.motions[0]);
  std::string header;
  std::getline(in, header);
  std::set<std::string> props;
  const Json parsed = Json::parse(header);
  for (const Json& p : parsed.at("props")) props.insert(p.at("name").get<std::string>());
  for (const char* name : {"front_block", "rear_block", "start_line", "finish_line", "lane_left", "lane_right"})
    EXPECT_TRUE(props.count(name)) << name;
  // The reports: JSON with every episode, a plain table, a result table of one row per episode.
  const Json j = a.to_json();
  EXPECT_EQ(j["episodes"].size(), 3u);
  EXPECT_EQ(j["summary"]["episodes"], 3);
  EXPECT_FALSE(j["summary"]["wind_check"].is_null());
  EXPECT_EQ(a.result_table()["rows"].size(), 3u);
  EXPECT_NE(a.text_table().find("wind check"), std::string::npos);
  std::printf("%s", a.text_table().c_str());
}

// Scripted policies: the Start follows its reference (the frame after the observation's phase,
// of the reference its one-hot names); stage 2 holds the standing pose.
RacePolicyFns scripted_policies(const RaceEnvSettings& e) {
  const auto bridge = std::make_shared<const character::PoseBridge>(sim::load_shipped_model("humanoid34"));
  const std::vector<StartReference> refs = e.start.start_references;
  RacePolicyFns p;
  p.start = [bridge, refs](std::span<const double> o, std::span<double> a) {
    const std::size_t n = refs.size(), size = o.size();
    std::size_t r = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (o[size - n - 1 + k] > 0.5) r = k;
    const character::Clip& clip = *refs[r].clip;
    const auto frame = static_cast<std::size_t>(std::lround(o[size - n - 2] * clip.duration_s() * 30.0)) + 1;
    const std::vector<double> pose = bridge->pose(clip.poses[std::min(frame, clip.size() - 1)]);
    std::copy(pose.begin(), pose.end(), a.begin());
  };
  const std::vector<double> standing = bridge->pose(bridge->model().standing_pose());
  p.accelerate = [standing](std::span<const double>, std::span<double> a) {
    std::copy(standing.begin(), standing.end(), a.begin());
  };
  return p;
}

// The race's two phases and the dip on scripted policies: the Start hands over at its first
// landing past the line (the scripted start, the reference's poses as targets, falls out of the
// crouch starts before the line but lands from DeepMimic's run, a user start at the line), stage 2
// goes on from that state with its step count; a dip of 0° changes nothing but where it fired, a
// dip of 30° changes the run from the hand-over on, and only there.
TEST(SprintRace, StageTwoTakesOverAtTheLandingAndTheDipActsFromItsDistance) {
  const std::filesystem::path run = podium::testing::shared_data("deepmimic/data/motions/humanoid3d_run.txt");
  if (run.empty()) GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR): no start that lands";
  podium::testing::TempDir dir;
  RaceSettings settings;
  settings.start_clips = {{run.string(), "none"}};
  settings.sim_hz = 150.0;
  settings.episodes = 6;
  settings.record = 0;
  settings.wind_check = false;
  const RacePolicyFns policies = scripted_policies(race_env_settings(settings));
  const RaceReport plain = run_race(settings, policies, dir.path());
  const auto without_dip = [](const RaceEpisode& e) {
    Json j = e.to_json();
    j.erase("dip_x_m");
    return j;
  };
  int landed = 0;
  for (const RaceEpisode& e : plain.episodes) {
    if (!e.landing_time_s) {
      EXPECT_TRUE(e.outcome == "fell" || e.outcome == "left_lane" || e.outcome == "no_landing") << e.outcome;
      continue;
    }
    ++landed;
    EXPECT_GE(e.steps, 1);                // the landing counted, and the count went on in stage 2
    EXPECT_NE(e.outcome, "no_landing");   // stage 2's own end
    EXPECT_FALSE(e.dip_x_m.has_value());  // no dip by default
    EXPECT_EQ(e.lean_per_step_rad.size(), static_cast<std::size_t>(e.steps));
  }
  ASSERT_GT(landed, 0);
  RaceSettings zero = settings;
  zero.dip = DipParams{100.0, 0.0};  // within 100 m of the line from the start: fires at stage 2's first step
  RaceSettings thirty = settings;
  thirty.dip = DipParams{100.0, 30.0};
  RaceSettings far = thirty;
  far.dip->distance_m = 0.5;  // never that close
  const RaceReport a = run_race(zero, policies, dir.path()), b = run_race(thirty, policies, dir.path()),
                   c = run_race(far, policies, dir.path());
  int changed = 0;
  for (std::size_t k = 0; k < plain.episodes.size(); ++k) {
    const RaceEpisode& e = plain.episodes[k];
    EXPECT_EQ(without_dip(a.episodes[k]), without_dip(e)) << k;
    EXPECT_EQ(c.episodes[k].to_json(), e.to_json()) << k;
    EXPECT_EQ(a.episodes[k].dip_x_m.has_value(), e.landing_time_s.has_value()) << k;
    if (!e.landing_time_s) {
      EXPECT_EQ(b.episodes[k].to_json(), e.to_json()) << k;  // the Start phase is not the dip's
      continue;
    }
    EXPECT_EQ(b.episodes[k].dip_x_m, a.episodes[k].dip_x_m) << k;
    if (without_dip(b.episodes[k]) != without_dip(e)) ++changed;
  }
  EXPECT_EQ(changed, landed);
  // The dip check: every episode again without the dip, which is the race without one, paired.
  ASSERT_EQ(b.no_dip.size(), plain.episodes.size());
  EXPECT_TRUE(plain.no_dip.empty());
  std::vector<double> gain;
  int added_falls = 0;
  for (std::size_t k = 0; k < plain.episodes.size(); ++k) {
    EXPECT_EQ(b.no_dip[k].to_json(), plain.episodes[k].to_json()) << k;
    const auto &none = plain.episodes[k].finish_time_s, &dip = b.episodes[k].finish_time_s;
    if (none && dip) gain.push_back(*none - *dip);
    if (none && !dip) ++added_falls;
  }
  const Json check = b.summary()["dip_check"];
  EXPECT_TRUE(plain.summary()["dip_check"].is_null());
  EXPECT_EQ(check["pairs"], gain.size());
  EXPECT_EQ(check["added_falls"], added_falls);
  if (!gain.empty()) {
    EXPECT_NEAR(check["mean_gain_s"].get<double>(), std::accumulate(gain.begin(), gain.end(), 0.0) / gain.size(), 1e-12);
  }
  EXPECT_EQ(b.summary()["dip"], Json({{"distance_m", 100.0}, {"angle_deg", 30.0}}));
  EXPECT_NE(b.text_table().find("dip check, paired"), std::string::npos);
  EXPECT_EQ(plain.text_table().find("dip check"), std::string::npos);
}

}  // namespace
}  // namespace podium::tasks::sprint
