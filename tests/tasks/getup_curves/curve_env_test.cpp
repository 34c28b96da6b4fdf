// CurveGetupEnv on real physics (humanoid34, 600 Hz simulation, 30 Hz control): the state's
// blocks, the reward against eqs. 2–9 recomputed from the env's own state, a saved state's bitwise
// continuation, §5.3's head-down termination on a limp character, episodes of T + 3 s, curve files
// and (with ../shared/data) a clip start.
#include "curve_env.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

#include "curve_extraction.h"
#include "podium/base/error.h"
#include "podium/character/observations.h"
#include "podium/character/pose_bridge.h"
#include "podium/character/rewards.h"
#include "process.h"
#include "shared_data.h"

namespace podium::tasks::getup_curves {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

sim::ModelPtr humanoid() { return sim::load_shipped_model("humanoid34"); }

// From lying (h 0.2 m, on the back or front) to standing at humanoid34's neck height over T.
StyleCurve rising_curve(double duration_s, bool supine) {
  StyleCurve c;
  c.name = supine ? "rise from the back" : "rise from the front";
  c.duration_s = duration_s;
  const double stand_h = standing_neck_height(*humanoid());
  for (int k = 0; k < kControlPoints; ++k) {
    const double u = static_cast<double>(k) / (kControlPoints - 1);
    c.points(0, k) = 0.2 + (stand_h - 0.2) * u;
    c.points(1, k) = 90.0 * kDeg;
    c.points(2, k) = (supine ? 0.0 : 180.0) * kDeg + (supine ? 90.0 : -90.0) * kDeg * u;
  }
  c.start.kind = CurveStart::Kind::drop;
  c.start.supine = supine;
  c.source = "test";
  return c;
}

std::vector<double> random_action(const learn::BoxSpace& box, base::Rng& rng) {
  std::vector<double> a(box.size());
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = rng.uniform(box.low[k], box.high[k]);
  return a;
}

// The action that keeps the filter where it is (y = a when a = y_{t−1}).
std::vector<double> hold(const CurveGetupEnv& env) {
  const Eigen::VectorXd& y = env.filtered_action();
  return std::vector<double>(y.data(), y.data() + y.size());
}

std::size_t info_index(const std::string& name) {
  const std::vector<std::string> names = curve_env_info_names();
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}

TEST(CurveGetupEnv, StateIsLinkStatesFeaturesHeightMapTargetsAndTheFilteredAction) {
  const sim::ModelPtr model = humanoid();
  const StyleCurve curve = rising_curve(2.0, true);
  CurveGetupEnv env({}, make_curve_set({curve}, model));
  env.seed(1);
  std::vector<double> obs;
  env.reset(obs);
  // §3.3: q (4 per body), p v ω (9 per body), w (3), h (25), t (12), y_{t−1} (28 PD targets).
  const std::size_t bodies = model->bodies().size();
  const std::size_t actions = static_cast<std::size_t>(model->nv() - 6);
  ASSERT_EQ(obs.size(), 13 * bodies + 3 + 25 + 12 + actions);
  EXPECT_EQ(obs.size(), 263u);
  EXPECT_EQ(env.observation_space().size(), obs.size());
  EXPECT_EQ(env.action_space().size(), actions);
  const std::vector<std::string> names{"q", "p_v_omega", "w", "height_map", "targets", "previous_action"};
  const auto& blocks = env.observation_blocks();
  ASSERT_EQ(blocks.size(), names.size());
  std::size_t at = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    EXPECT_EQ(blocks[b].name, names[b]);
    EXPECT_EQ(blocks[b].offset, at);
    at += blocks[b].size;
  }
  EXPECT_EQ(at, obs.size());
  // Unit quaternions with w ≥ 0.
  for (std::size_t i = 0; i < bodies; ++i) {
    const double* r = &obs[4 * i];
    EXPECT_NEAR(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3], 1.0, 1e-12);
    EXPECT_GE(r[0], 0.0);
  }
  // w is the env's features; on flat ground the map is the root's height everywhere.
  const StyleFeatures w = env.achieved();
  for (int f = 0; f < 3; ++f) EXPECT_EQ(obs[blocks[2].offset + static_cast<std::size_t>(f)], w(f));
  EXPECT_EQ(env.ground_height_m(), 0.0);
  for (std::size_t k = 0; k < 25; ++k) EXPECT_NEAR(obs[blocks[3].offset + k], env.world().data().q(2), 1e-12);
  // Targets at 0, 100, 200, 300 ms, the four p_h first.
  for (int k = 0; k < 4; ++k)
    for (int f = 0; f < 3; ++f)
      EXPECT_NEAR(obs[blocks[4].offset + static_cast<std::size_t>(4 * f + k)], curve.target(0.1 * k)(f), 1e-12) << f << " " << k;
  // y_0 holds the start's pose; after a step the block is 0.2 a + 0.8 y_0 (§3.4).
  const character::PoseBridge bridge(model);
  const std::vector<double> pose = bridge.pose(env.world().data().q);
  const learn::BoxSpace box = env.action_space();
  std::vector<double> y0(actions);
  for (std::size_t k = 0; k < actions; ++k) {
    y0[k] = obs[blocks[5].offset + k];
    EXPECT_EQ(y0[k], std::clamp(pose[k], box.low[k], box.high[k]));
  }
  base::Rng rng(5);
  const std::vector<double> a = random_action(box, rng);
  learn::StepResult out;
  env.step(a, out);
  for (std::size_t k = 0; k < actions; ++k) EXPECT_NEAR(out.observation[blocks[5].offset + k], 0.2 * a[k] + 0.8 * y0[k], 1e-12);
  EXPECT_NEAR(out.observation[blocks[4].offset], curve.target(1.0 / 30.0)(0), 1e-12);
}

TEST(CurveGetupEnv, RewardIsEquationsTwoToNineOnTheEnvsOwnState) {
  const sim::ModelPtr model = humanoid();
  const StyleCurve curve = rising_curve(1.0, true);
  CurveEnvSettings settings;
  settings.early_termination = false;  // through T, where α reaches 1
  CurveGetupEnv env(settings, make_curve_set({curve}, model));
  env.seed(2);
  base::Rng rng(3);
  std::vector<double> obs;
  env.reset(obs);
  const StyleFeatureReader reader(*model);
  learn::StepResult out;
  double max_alpha = 0.0;
  for (int step = 1; step <= 40; ++step) {
    env.step(random_action(env.action_space(), rng), out);
    ASSERT_FALSE(out.terminated) << "step " << step;
    const sim::CharacterData& d = env.world().data();
    const StyleFeatures w = reader(d, 0.0);  // flat ground
    const StyleFeatures p = curve.target(step * (1.0 / 30.0));
    std::vector<Eigen::Vector3d> omega, velocity;
    character::link_velocities(*model, d, omega, velocity);
    double omega_sq = 0.0;
    for (const Eigen::Vector3d& o : omega) omega_sq += o.squaredNorm();
    const double alpha = standing_phase(p(0), curve.at(1.0)(0));
    const double r_h = height_reward(w(0), p(0));
    const double r_theta = torso_reward(w(1), w(2), p(1), p(2));
    const double r_v = velocity_reward(alpha, std::sqrt(omega_sq));
    const double r_p = pose_reward(alpha, joint_rotation_distance(*model, d.q, model->standing_pose()));
    const double r_natural = character::naturalness_reward_from_norm(0.0, 10.0);  // PD targets: no Δq
    EXPECT_NEAR(out.reward, r_h * r_theta * r_v * r_p * r_natural, 1e-12) << "step " << step;
    EXPECT_NEAR(out.info[info_index("r_h")], r_h, 1e-12);
    EXPECT_NEAR(out.info[info_index("r_theta")], r_theta, 1e-12);
    EXPECT_NEAR(out.info[info_index("alpha")], alpha, 1e-12);
    EXPECT_NEAR(out.info[info_index("r_v")], r_v, 1e-12);
    EXPECT_NEAR(out.info[info_index("r_p")], r_p, 1e-12);
    EXPECT_EQ(out.info[info_index("r_natural")], 1.0);
    EXPECT_EQ(out.info[info_index("h")], w(0));
    EXPECT_NEAR(out.info[info_index("target_theta_z")], p(2), 1e-12);
    const bool head = env.features().touches(model->head_body(), sim::Contact::Partner::ground);
    EXPECT_EQ(out.info[info_index("head_on_ground")], head ? 1.0 : 0.0);
    max_alpha = std::max(max_alpha, alpha);
  }
  EXPECT_EQ(max_alpha, 1.0);  // past T the curve is at its end: φ = 1
}

TEST(CurveGetupEnv, SavedStateContinuesTwentyStepsBitwise) {
  const sim::ModelPtr model = humanoid();
  const auto curves = make_curve_set({rising_curve(2.0, true), rising_curve(1.5, false)}, model);
  CurveEnvSettings settings;
  settings.early_termination = false;  // 25 steps from lying; the counters are still saved and compared
  CurveGetupEnv env(settings, curves);
  env.seed(4);
  base::Rng rng(6);
  std::vector<double> obs;
  env.reset(obs);
  learn::StepResult out;
  for (int i = 0; i < 5; ++i) env.step(random_action(env.action_space(), rng), out);
  const base::Json saved = *env.save_state();
  std::vector<std::vector<double>> actions;
  std::vector<learn::StepResult> expected;
  for (int i = 0; i < 20; ++i) {
    actions.push_back(random_action(env.action_space(), rng));
    env.step(actions.back(), out);
    expected.push_back(out);
  }
  CurveGetupEnv copy(settings, curves);
  copy.seed(99);
  std::vector<double> other;
  copy.reset(other);  // another episode first: the load replaces it
  copy.load_state(base::Json::parse(saved.dump()));
  EXPECT_EQ(copy.curve_index(), env.curve_index());
  for (std::size_t i = 0; i < actions.size(); ++i) {
    copy.step(actions[i], out);
    EXPECT_EQ(out.observation, expected[i].observation) << "step " << i;
    EXPECT_EQ(out.reward, expected[i].reward) << "step " << i;
    EXPECT_EQ(out.terminated, expected[i].terminated);
    EXPECT_EQ(out.truncated, expected[i].truncated);
    EXPECT_EQ(out.info, expected[i].info) << "step " << i;
  }
  EXPECT_TRUE(copy.filtered_action() == env.filtered_action());
}

TEST(CurveGetupEnv, HeadOnTheGroundEndsALimpEpisodeAtTheTenthStep) {
  const sim::ModelPtr model = humanoid();
  // A curve that starts at this drop's own features and rises slowly (T = 8 s): r_h = r_θ ≈ 1 and
  // α ≈ 0 at first, so r_task stays high and only the head can end the episode.
  StyleCurve curve = rising_curve(8.0, true);
  {
    CurveGetupEnv probe({}, make_curve_set({curve}, model));
    probe.seed(7);
    std::vector<double> obs;
    probe.reset(obs);
    const StyleFeatures w = probe.achieved();
    for (int k = 0; k < 3; ++k) curve.points.col(k) = w;
  }
  CurveGetupEnv env({}, make_curve_set({curve}, model));
  env.seed(7);
  std::vector<double> obs;
  env.reset(obs);
  env.world().set_strength(0.0);  // zero torques: the character lies limp
  EarlyTermination rule(1.0 / 30.0);
  learn::StepResult out;
  int steps = 0;
  do {
    env.step(hold(env), out);
    ++steps;
    const bool head = out.info[info_index("head_on_ground")] == 1.0;
    EXPECT_TRUE(head) << "step " << steps;
    EXPECT_GE(out.info[info_index("r_task")], 0.1) << "step " << steps;
    EXPECT_EQ(out.terminated, rule.step(out.info[info_index("r_task")], head)) << "step " << steps;
  } while (!out.terminated && steps < 30);
  EXPECT_TRUE(out.terminated);
  EXPECT_EQ(steps, 10);  // more than 300 ms at 30 Hz, not the 9th step
  EXPECT_EQ(out.info[info_index("head_down_steps")], 10.0);
  EXPECT_EQ(out.info[info_index("low_task_steps")], 0.0);
  EXPECT_EQ(out.info[info_index("success")], 0.0);
}

TEST(CurveGetupEnv, AnEpisodeLastsTPlusThreeSecondsOfControlSteps) {
  const sim::ModelPtr model = humanoid();
  CurveEnvSettings settings;
  settings.early_termination = false;
  CurveGetupEnv env(settings, make_curve_set({rising_curve(0.5, true), rising_curve(1.2, false)}, model));
  env.seed(8);
  for (int curve = 0; curve < 2; ++curve) {
    env.use_curve(curve);
    std::vector<double> obs;
    env.reset(obs);
    const int expected = static_cast<int>(std::lround((env.curve().duration_s + 3.0) * 30.0));
    EXPECT_EQ(env.episode_length(), expected);
    learn::StepResult out;
    int steps = 0;
    do {
      env.step(hold(env), out);
      ++steps;
      ASSERT_FALSE(out.terminated);
      EXPECT_EQ(out.truncated, steps == expected) << "step " << steps;
    } while (!out.truncated && steps < 1000);
    EXPECT_EQ(steps, expected) << "curve " << curve;
    EXPECT_FALSE(env.succeeded());  // lying at the end: h far below 0.9 p_h(1)
  }
  EXPECT_EQ(env.episode_length(), 126);  // (1.2 + 3) s at 30 Hz
}

TEST(CurveGetupEnv, CurveFilesLoadAndABadClipIsNamed) {
  const sim::ModelPtr model = humanoid();
  podium::testing::TempDir dir;
  save_style_curve(dir / "rise.json", rising_curve(2.5, false));
  const auto set = load_curve_set({dir / "rise.json"}, model);
  ASSERT_EQ(set->curves.size(), 1u);
  EXPECT_EQ(set->curves[0].name, "rise from the front");
  EXPECT_FALSE(set->clips[0]);
  StyleCurve clip_start = rising_curve(2.5, true);
  clip_start.start = {CurveStart::Kind::clip, "absent.txt", 0, true};
  save_style_curve(dir / "absent.json", clip_start);
  try {
    load_curve_set({dir / "rise.json", dir / "absent.json"}, model);
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find((dir / "absent.json").string()), std::string::npos) << what;
    EXPECT_NE(what.find("start.clip: \"absent.txt\""), std::string::npos) << what;
  }
  CurveGetupEnv env({}, set);
  EXPECT_THROW(env.use_curve(1), base::UserError);
  EXPECT_THROW(CurveGetupEnv({}, make_curve_set({}, model)), base::UserError);
}

// DeepMimic's supine get-up clip (../shared/data), or empty when PODIUM_SHARED_DIR is unset or the
// file absent.
std::filesystem::path faceup_clip() { return podium::testing::shared_data("deepmimic/data/motions/humanoid3d_getup_faceup.txt"); }

// §5.2 (ii) with clips: a standing start on flat is a frame of a clip's last standing_tail_s
// (its pose exactly, without noise), entered at the curve's standing part; with a tail of 0 it is
// the model's standing pose.
TEST(CurveGetupStarts, AStandingStartOnFlatIsAFrameOfAClipsStandingEnd) {
  const std::filesystem::path clip = faceup_clip();
  if (clip.empty()) GTEST_SKIP() << "PODIUM_SHARED_DIR or humanoid3d_getup_faceup.txt absent";
  podium::testing::TempDir dir;
  std::filesystem::copy_file(clip, dir / "faceup.txt");
  StyleCurve curve = rising_curve(3.8, true);
  curve.start = {CurveStart::Kind::clip, "faceup.txt", 0, true};
  save_style_curve(dir / "faceup.json", curve);
  const auto set = load_curve_set({dir / "faceup.json"}, humanoid());
  const character::Clip& frames = *set->clips[0];
  CurveEnvSettings settings;
  settings.standing_share = 1.0;
  settings.clip_start_noise_rad = 0.0;
  settings.standing_tail_s = 0.2;
  CurveGetupEnv env(settings, set);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    env.seed(seed);
    std::vector<double> obs;
    env.reset(obs);
    ASSERT_TRUE(env.standing_start());
    EXPECT_DOUBLE_EQ(env.curve_time_s(), curve.duration_s);
    const Eigen::VectorXd& q = env.world().data().q;
    // The nearest frame of the clip's last 0.2 s (a sample between two frames lies within their span).
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < frames.size(); ++f) {
      if (frames.times_s[f] < frames.duration_s() - 0.2 - 0.05) continue;
      nearest = std::min(nearest, (q.tail(q.size() - 7) - frames.poses[f].tail(q.size() - 7)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(nearest, 0.05) << seed;
    const double h = env.achieved()(0);
    EXPECT_GT(h, 0.9 * curve.at(1.0)(0)) << seed;  // standing: h near the curve's end
    learn::StepResult out;
    for (int step = 0; step < 15; ++step) env.step(hold(env), out);
    std::printf("seed %llu: h %.3f m, after 0.5 s %.3f m\n", static_cast<unsigned long long>(seed), h, env.achieved()(0));
    EXPECT_GT(env.achieved()(0), h - 0.3) << seed;  // not fallen within half a second
  }
  settings.standing_tail_s = 0.0;
  CurveGetupEnv model_pose(settings, set);
  model_pose.seed(1);
  std::vector<double> obs;
  model_pose.reset(obs);
  EXPECT_NEAR(model_pose.world().data().q(2), model_pose.model().standing_pose()(2), 1e-12);
}

TEST(CurveGetupEnv, AClipStartBeginsInItsFrameOnTheBack) {
  const std::filesystem::path clip = faceup_clip();
  if (clip.empty()) GTEST_SKIP() << "PODIUM_SHARED_DIR or humanoid3d_getup_faceup.txt absent";
  const sim::ModelPtr model = humanoid();
  podium::testing::TempDir dir;
  std::filesystem::copy_file(clip, dir / "faceup.txt");
  StyleCurve curve = rising_curve(3.8, true);
  curve.start = {CurveStart::Kind::clip, "faceup.txt", 0, true};  // relative to the curve file
  save_style_curve(dir / "faceup.json", curve);
  StyleCurve slower = curve;
  slower.duration_s = 5.0;
  save_style_curve(dir / "faceup_slow.json", slower);
  const auto set = load_curve_set({dir / "faceup.json", dir / "faceup_slow.json"}, model);
  ASSERT_TRUE(set->clips[0]);
  EXPECT_EQ(set->clips[1], set->clips[0]);  // two curve files on one clip: read once
  CurveEnvSettings settings;
  settings.clip_start_noise_rad = 0.0;
  CurveGetupEnv env(settings, set);
  env.seed(9);
  std::vector<double> obs;
  env.reset(obs);
  const Eigen::VectorXd& q = env.world().data().q;
  const Eigen::VectorXd frame = set->clips[0]->poses[0];
  EXPECT_LT((q.tail(q.size() - 7) - frame.tail(frame.size() - 7)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(env.achieved()(2), 15.0 * kDeg);  // on the back, as the clip
}

}  // namespace
}  // namespace podium::tasks::getup_curves

namespace podium::tasks::getup_curves {
namespace {

// §3.2's terrain: each region above flat is a rough half and a slope half; §5.4: a drop lands on
// a level among the open ones (flat at the origin, a harder one inside one of its parts), and
// every ended episode is reported once with its level and success.
TEST(CurveGetupTerrain, DropsLandOnTheOpenLevelsAndEndedEpisodesAreReported) {
  CurveEnvSettings settings;
  settings.terrain.levels = 3;
  settings.early_termination = false;
  const sim::TerrainConfig terrain = terrain_config(settings.terrain);
  ASSERT_EQ(terrain.regions.size(), 4u);  // easy and medium, rough and slope each
  EXPECT_EQ(terrain.regions[0].kind, sim::TerrainRegion::Kind::rough);
  EXPECT_EQ(terrain.regions[1].kind, sim::TerrainRegion::Kind::slope);
  EXPECT_DOUBLE_EQ(terrain.regions[0].max_tile_height_m, 0.02);
  EXPECT_NEAR(terrain.regions[3].slope_rad, 20.0 * kDeg, 1e-12);
  CurveGetupEnv env(settings, make_curve_set({rising_curve(0.2, true)}, humanoid()));
  env.seed(4);
  std::vector<double> obs;
  env.reset(obs);
  EXPECT_EQ(env.level(), 0);  // one level open: flat, at the origin
  EXPECT_EQ(env.world().terrain().region_at(env.world().data().q(0), env.world().data().q(1)), -1);
  EXPECT_THROW(env.set_open_levels(4), base::UserError);
  env.set_open_levels(3);
  std::set<int> seen;
  for (int episode = 0; episode < 12; ++episode) {
    env.reset(obs);
    seen.insert(env.level());
    const int region = env.world().terrain().region_at(env.world().data().q(0), env.world().data().q(1));
    EXPECT_EQ(region < 0 ? 0 : region / 2 + 1, env.level()) << episode;  // the drop is on its level's ground
  }
  EXPECT_EQ(seen, (std::set<int>{0, 1, 2}));
  env.use_level(2);
  env.take_finished();
  env.reset(obs);
  learn::StepResult out;
  do env.step(hold(env), out);
  while (!out.terminated && !out.truncated);
  EXPECT_EQ(out.info[info_index("level")], 2.0);
  EXPECT_EQ(env.take_finished(), (std::vector<std::pair<int, bool>>{{2, env.succeeded()}}));
  EXPECT_TRUE(env.take_finished().empty());
}

}  // namespace
}  // namespace podium::tasks::getup_curves

namespace podium::tasks::getup_curves {
namespace {

// §5.2: after a drop, a curve whose initial torso angles are more than 30° from the torso's is
// replaced by one that is near: a curve that asks to start prone but drops supine gives way to
// the supine one.
TEST(CurveGetupStarts, TheThirtyDegreeFilterReplacesACurveTheDropDoesNotMatch) {
  StyleCurve prone_target = rising_curve(0.5, false);  // θ_z(0) = 180°
  prone_target.name = "asks prone, drops supine";
  prone_target.start.supine = true;
  CurveGetupEnv env({}, make_curve_set({prone_target, rising_curve(0.5, true)}, humanoid()));
  env.seed(11);
  std::vector<double> obs;
  const auto near = [&](int k) {
    const StyleFeatures p = env.curves().curves[static_cast<std::size_t>(k)].at(0.0), w = env.achieved();
    return std::abs(p(1) - w(1)) <= 30.0 * kDeg && std::abs(p(2) - w(2)) <= 30.0 * kDeg;
  };
  int filtered = 0;
  for (int episode = 0; episode < 20; ++episode) {
    env.reset(obs);
    if (near(0) || near(1)) {
      EXPECT_TRUE(near(env.curve_index())) << episode;  // a near curve when there is one
    }
    if (!near(0) && near(1)) {  // only the supine one fits: whichever was drawn, it is used
      EXPECT_EQ(env.curve_index(), 1) << episode;
      ++filtered;
    }
  }
  EXPECT_GT(filtered, 0);
  CurveEnvSettings off;
  off.curve_filter_rad = 0.0;  // no filter: the drawn curve stays
  CurveGetupEnv unfiltered(off, make_curve_set({prone_target}, humanoid()));
  unfiltered.seed(11);
  unfiltered.reset(obs);
  EXPECT_EQ(unfiltered.curve_index(), 0);
}

// §5.2 (ii) off flat: a standing start on the hard level's 30° slope and ±10 cm tiles stands at a
// drop site with each sole turned to the surface under it (its normal within 1° of the surface's),
// the lower foot on the surface and no foot corner below it; the next half second it stays up.
TEST(CurveGetupStarts, AStandingStartOffFlatTurnsTheFeetToTheSurface) {
  CurveEnvSettings settings;
  settings.terrain.levels = 4;
  settings.standing_share = 1.0;
  settings.early_termination = false;
  CurveGetupEnv env(settings, make_curve_set({rising_curve(1.0, true)}, humanoid()));
  env.set_open_levels(4);
  env.use_level(3);
  const sim::CharacterModel& m = env.model();
  const sim::Terrain& terrain = env.world().terrain();
  std::set<sim::TerrainRegion::Kind> kinds;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    env.seed(seed);
    std::vector<double> obs;
    env.reset(obs);
    ASSERT_TRUE(env.standing_start());
    const sim::CharacterData& d = env.world().data();
    const int region = terrain.region_at(d.q(0), d.q(1));
    ASSERT_GE(region, 4) << seed;  // the hard level's rough (4) or slope (5) half
    kinds.insert(terrain.config().regions[static_cast<std::size_t>(region)].kind);
    double lowest = std::numeric_limits<double>::infinity();
    for (const char* ankle : {"right_ankle", "left_ankle"}) {
      const int link = m.find_link(ankle);
      const auto& foot = d.links[static_cast<std::size_t>(link)];
      const bool slope = terrain.config().regions[static_cast<std::size_t>(region)].kind == sim::TerrainRegion::Kind::slope;
      const Eigen::Vector3d normal =
          slope ? Eigen::Vector3d(-std::sin(30.0 * kDeg), 0.0, std::cos(30.0 * kDeg)) : Eigen::Vector3d::UnitZ();
      EXPECT_LT(std::acos(std::min(1.0, foot.R.col(2).dot(normal))), 1.0 * kDeg) << seed << " " << ankle;
      const auto& g = m.links()[static_cast<std::size_t>(link)].geoms.front();
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d c((k & 1 ? 1 : -1) * g.half_extents.x(), (k & 2 ? 1 : -1) * g.half_extents.y(),
                                (k & 4 ? 1 : -1) * g.half_extents.z());
        const Eigen::Vector3d w = foot.p + foot.R * (g.pos + c);
        const double above = w.z() - terrain.height(w.x(), w.y());
        EXPECT_GT(above, -1e-9) << seed << " " << ankle;
        lowest = std::min(lowest, above);
      }
    }
    EXPECT_NEAR(lowest, 0.0, 1e-9) << seed;
    const double neck = env.world().data().links[static_cast<std::size_t>(m.find_link("neck"))].p.z();
    learn::StepResult out;
    for (int step = 0; step < 15; ++step) env.step(hold(env), out);
    const double after = env.world().data().links[static_cast<std::size_t>(m.find_link("neck"))].p.z();
    std::printf("seed %llu, region %d: neck %.3f m, after 0.5 s %.3f m\n", static_cast<unsigned long long>(seed), region, neck,
                after);
    EXPECT_GT(after, neck - 0.3) << seed;  // not fallen within half a second
  }
  EXPECT_EQ(kinds.size(), 2u);  // both halves met
}

// §5.2 (ii): a standing start on flat, with no clip in the set, stands in the model's standing
// pose, entered at the curve's standing part (s = 1 from the first step) for T_stand, and does not
// count for the curriculum.
TEST(CurveGetupStarts, AStandingStartEntersTheCurveAtItsStandingPart) {
  CurveEnvSettings settings;
  settings.standing_share = 1.0;
  settings.early_termination = false;
  const StyleCurve curve = rising_curve(1.0, true);
  CurveGetupEnv env(settings, make_curve_set({curve}, humanoid()));
  env.seed(2);
  std::vector<double> obs;
  env.reset(obs);
  ASSERT_TRUE(env.standing_start());
  EXPECT_NEAR(env.world().data().q(2), env.model().standing_pose()(2), 1e-12);
  EXPECT_DOUBLE_EQ(env.curve_time_s(), curve.duration_s);
  EXPECT_EQ(env.episode_length(), 90);  // T_stand at 30 Hz
  learn::StepResult out;
  int steps = 0;
  do env.step(hold(env), out), ++steps;
  while (!out.terminated && !out.truncated);
  EXPECT_EQ(steps, 90);
  EXPECT_EQ(out.info[info_index("target_h")], curve.at(1.0)(0));
  EXPECT_TRUE(env.take_finished().empty());
  env.set_standing_share(0.0);
  env.reset(obs);
  EXPECT_FALSE(env.standing_start());
  EXPECT_EQ(env.curve_time_s(), 0.0);
  EXPECT_THROW(env.set_standing_share(1.5), base::UserError);
}

}  // namespace
}  // namespace podium::tasks::getup_curves
