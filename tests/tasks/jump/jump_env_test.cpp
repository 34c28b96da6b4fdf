// JumpEnv on real Bullet: observation layout, props that follow z, the composite action space and
// its naturalness term, checkpoint round trip, and random rollouts from the take-off state.
#include "jump_env.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "jump_evaluation.h"
#include "jump_test_util.h"
#include "podium/base/error.h"

namespace podium::tasks::jump {
namespace {

using testing::settings;

bool finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

std::vector<double> random_action(const learn::BoxSpace& box, base::Rng& rng) {
  std::vector<double> a(box.size());
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = rng.uniform(box.low[k], box.high[k]);
  return a;
}

TEST(JumpEnv, ObservationIsGlobalLinkStatesRootPositionAndZ) {
  JumpEnv env(settings(JumpKind::high_jump, 0.8));
  std::vector<double> obs;
  env.reset(obs);
  const std::size_t bodies = env.model().bodies().size();
  ASSERT_EQ(obs.size(), 15 * bodies + 4);
  EXPECT_EQ(obs.size(), env.observation_space().size());
  EXPECT_DOUBLE_EQ(obs.back(), 0.8);
  EXPECT_DOUBLE_EQ(obs[15 * bodies], 0.0);  // the root starts over the take-off point
  // The take-off state runs at 6 m/s along +x: the root body's world velocity (entries 9..11).
  EXPECT_NEAR(obs[9], 6.0, 1e-9);
  EXPECT_EQ(env.world().config().control_hz, 20.0);  // ρ = 0.6: 22 Hz, between 20 and 24: the lower
  EXPECT_EQ(env.episode_steps(), static_cast<int>(std::ceil(2.0 * env.world().config().control_hz)));
  EXPECT_DOUBLE_EQ(env.c_offset(), offset_coefficient(0.6));
}

TEST(JumpEnv, PropsMoveAndResizeWhenZChanges) {
  JumpEnv env(settings(JumpKind::high_jump, 0.5));
  const auto& boxes = [&] { return env.world().terrain().config().boxes; };
  EXPECT_NEAR(boxes()[0].half_extents.z(), 0.25, 1e-12);
  EXPECT_NEAR(boxes()[1].center.z() * 2, 0.02, 1e-12);  // block top clip(z − 0.7, 0.02, 0.75)
  EXPECT_TRUE(env.set_difficulty(0.51));                // 10 + 20·0.02 = 10.4 Hz still rounds to 10
  EXPECT_FALSE(env.set_difficulty(1.2));                // 30 Hz: a new env is needed
  EXPECT_NEAR(boxes()[0].half_extents.z(), 0.6, 1e-12);
  EXPECT_NEAR(boxes()[0].center.z(), 0.6, 1e-12);
  EXPECT_NEAR(boxes()[1].center.z() * 2, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(env.c_offset(), 15.0);
  std::vector<double> obs;
  env.reset(obs);
  EXPECT_DOUBLE_EQ(obs.back(), 1.2);
  EXPECT_NEAR(env.world().terrain().height(1.225, 0.0), 1.2, 1e-9);  // the wall's top, as the World sees it

  JumpEnv box(settings(JumpKind::obstacle, 0.5));
  EXPECT_NEAR(box.world().terrain().config().boxes[0].half_extents.x(), 0.25, 1e-12);  // width z along the run
  box.set_difficulty(2.0);
  const auto& obstacle = box.world().terrain().config().boxes[0];
  EXPECT_NEAR(obstacle.half_extents.x(), 1.0, 1e-12);
  EXPECT_NEAR(obstacle.center.x(), 1.0 + 1.0, 1e-12);
  EXPECT_NEAR(obstacle.half_extents.z(), 0.25, 1e-12);                                   // 50 cm high
  EXPECT_NEAR(box.world().terrain().config().boxes[1].center.x(), 3.02 + 2.0, 1e-12);    // block 2 cm after the box, 4 m deep
  EXPECT_NEAR(box.suite().signed_distance(Eigen::Vector3d(2.0, 5.0, 1.0)), 0.0, 1e-12);  // the centre plane
}

TEST(JumpEnv, ApproachAngleTurnsTheSuiteAboutTheTakeoffPoint) {
  JumpSettings s = settings();
  s.takeoff_features = {0.0, 0.5, -1.0, 1.5};  // α = 0: the bar parallel to the run, on the left
  JumpEnv env(s);
  const sim::BoxProp& wall = env.world().terrain().config().boxes[0];
  EXPECT_NEAR(wall.center.x(), 0.0, 1e-12);
  EXPECT_NEAR(wall.center.y(), 1.225, 1e-12);
  EXPECT_NEAR(env.suite().plane_normal.y(), 1.0, 1e-12);
  std::vector<double> obs;
  env.reset(obs);
  const sim::CharacterData& d = env.world().data();
  const Eigen::Vector3d omega = d.links[0].R * d.qd.head<3>(), v = d.links[0].R * d.qd.segment<3>(3);
  EXPECT_LT((omega - Eigen::Vector3d(0.5, -1.0, kHighJumpTurnRate)).norm(), 1e-9);
  EXPECT_NEAR(v.y(), 1.5, 1e-9);
  EXPECT_NEAR(v.x(), 6.0, 1e-9);
}

TEST(JumpEnv, CompositeTargetsAddTheirOffsetsToTheNaturalnessTerm) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const character::PoseBridge bridge(model);
  auto vae = std::make_shared<learn::PoseVae>(learn::VaeConfig::pose_vae(), bridge.lower(), bridge.upper(), 0, 7);
  JumpEnv env(settings(), PosePrior{vae});
  ASSERT_EQ(env.action_space().size(), 13u + bridge.size());  // thesis §3.4.2: d_latent + d_offset
  EXPECT_EQ(env.action_space().high.back(), 2.0);
  std::vector<double> obs;
  env.reset(obs);
  testing::place(env, {3.0, 0.0, env.model().standing_pose()(2) + 0.03});  // just above the block
  std::vector<double> action(env.action_space().size(), 0.0);
  for (std::size_t k = 13; k < action.size(); ++k) action[k] = k % 2 ? 0.5 : -0.5;  // ‖a_offset‖₁ = 14 rad
  learn::StepResult out;
  for (int i = 0; i < 10 && !out.terminated; ++i) env.step(action, out);
  ASSERT_EQ(env.outcome(), Outcome::success) << env.outcome_reason();
  const double l1 = 0.5 * static_cast<double>(bridge.size());
  EXPECT_NEAR(env.reward_terms().naturalness, 1.0 - (l1 / 48.0) * (l1 / 48.0), 1e-12);
  EXPECT_NEAR(out.info[4], l1, 1e-12);
}

TEST(JumpEnv, SavedStateContinuesTheEpisodeBitwise) {
  JumpEnv env(settings(JumpKind::high_jump, 1.0));
  env.seed(4);
  base::Rng rng(11);
  std::vector<double> obs;
  env.reset(obs);
  learn::StepResult out;
  env.step(testing::hold_pose(env), out);
  ASSERT_FALSE(out.terminated) << env.outcome_reason();
  const base::Json saved = *env.save_state();
  std::vector<std::vector<double>> actions;
  std::vector<learn::StepResult> expected;
  while (!out.terminated && !out.truncated) {
    actions.push_back(random_action(env.action_space(), rng));
    env.step(actions.back(), out);
    expected.push_back(out);
  }
  JumpEnv copy(settings(JumpKind::high_jump, 1.1));  // another z at the same rate (30 Hz): the state carries z
  copy.load_state(base::Json::parse(saved.dump()));
  EXPECT_DOUBLE_EQ(copy.difficulty_m(), 1.0);
  EXPECT_EQ(copy.world().terrain().config().boxes[0].half_extents.z(), 0.5);
  for (std::size_t i = 0; i < actions.size(); ++i) {
    copy.step(actions[i], out);
    EXPECT_EQ(out.observation, expected[i].observation) << "step " << i;
    EXPECT_EQ(out.reward, expected[i].reward);
    EXPECT_EQ(out.terminated, expected[i].terminated);
  }
  EXPECT_EQ(copy.outcome(), env.outcome());
  EXPECT_EQ(copy.outcome_reason(), env.outcome_reason());
  EXPECT_EQ(copy.crossing().up_angle(), env.crossing().up_angle());
}

TEST(JumpEnv, RandomActionsFromTheTakeoffStateStayFiniteAndEndDecided) {
  for (JumpKind kind : {JumpKind::high_jump, JumpKind::obstacle}) {
    JumpEnv env(settings(kind, 0.5));
    env.seed(1);
    base::Rng rng(2);
    for (int episode = 0; episode < 3; ++episode) {
      std::vector<double> obs;
      env.reset(obs);
      learn::StepResult out;
      int steps = 0;
      do {
        env.step(random_action(env.action_space(), rng), out);
        ++steps;
        ASSERT_TRUE(finite(out.observation)) << jump_kind_name(kind) << " episode " << episode << " step " << steps;
      } while (!out.terminated && !out.truncated);
      EXPECT_TRUE(out.terminated);
      EXPECT_NE(env.outcome(), Outcome::in_flight);
      EXPECT_GE(out.reward, 0.0);
      EXPECT_LE(out.reward, 1.0);
      std::printf("%s episode %d: %s after %d steps (%s)\n", jump_kind_name(kind), episode, outcome_name(env.outcome()), steps,
                  env.outcome_reason().c_str());
    }
  }
}

// The replay's recording: ≥ 60 frames per simulated second at the quick preset's 150 Hz
// simulation and 10 Hz control, the props with their kinds, and the evaluation's numbers (success,
// feature, offsets) the same as without a recording.
TEST(JumpEvaluation, RecordsTheJumpAtSixtyHertzOrMoreWithoutChangingIt) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "podium_jump_eval_record";
  std::filesystem::remove_all(dir);
  JumpSettings s = settings(JumpKind::high_jump, 0.5);
  s.sim_hz = 150.0;
  JumpEnv env(s);
  ASSERT_EQ(env.world().config().control_hz, 10.0);
  const character::PolicyFn hold = [&env](std::span<const double>, std::span<double> action) {
    const std::vector<double> pose = testing::hold_pose(env);
    std::copy(pose.begin(), pose.end(), action.begin());
  };
  const EvaluationJumps jumps{.jumps = 2, .sigma = 0.1, .seed = 4};
  const JumpEvaluation plain = evaluate_jumps(env, hold, jumps);
  const JumpEvaluation recorded = evaluate_jumps(env, hold, jumps, dir);
  EXPECT_EQ(recorded.success_rate, plain.success_rate);
  EXPECT_EQ(recorded.return_mean, plain.return_mean);
  EXPECT_EQ(recorded.mean_offset_l1, plain.mean_offset_l1);
  EXPECT_EQ(recorded.up_angle_rad, plain.up_angle_rad);
  EXPECT_EQ(recorded.bar_rotation, plain.bar_rotation);
  EXPECT_EQ(recorded.crossed, plain.crossed);
  ASSERT_FALSE(recorded.trajectory.empty());

  std::ifstream in(recorded.trajectory);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const base::Json header = base::Json::parse(line);
  ASSERT_EQ(header["props"].size(), 2u);
  EXPECT_EQ(header["props"][0]["kind"], "crossbar");
  EXPECT_EQ(header["props"][1]["kind"], "mat");
  std::vector<double> times;
  while (std::getline(in, line))
    if (!line.empty()) times.push_back(base::Json::parse(line)["t"].get<double>());
  ASSERT_GT(times.size(), 10u);
  // 15 simulation steps per control step: every 3rd would be 50 Hz, so every one (150 Hz).
  for (std::size_t f = 1; f < times.size(); ++f) EXPECT_NEAR(times[f] - times[f - 1], 1.0 / 150.0, 1e-5);
  EXPECT_GE(static_cast<double>(times.size() - 1) / (times.back() - times.front()), 60.0);
  std::filesystem::remove_all(dir);
}

TEST(JumpEnv, BadSettingsAreRejectedWithTheirName) {
  JumpSettings s = settings();
  s.takeoff_foot = "tail";
  EXPECT_THROW({ JumpEnv env(s); }, base::UserError);
  s = settings();
  s.takeoff_features = {1.0};
  EXPECT_THROW({ JumpEnv env(s); }, base::UserError);
  s = settings();
  s.takeoff_state = "state.csv";
  EXPECT_THROW({ JumpEnv env(s); }, base::UserError);
  const base::Json config = {{"kind", "obstacle"}, {"takeoff_features", {1.0, 2.0}}};
  base::ConfigReader r(config, "", "jump config");
  try {
    read_jump_settings(r);
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("takeoff_features"), std::string::npos) << e.what();
  }
}

TEST(JumpEnv, SettingsReadFromConfig) {
  const base::Json config = {
      {"kind", "obstacle"}, {"model", "athlete"}, {"difficulty_m", 0.3}, {"takeoff_features", {1.0, 2.0, 3.0}}};
  const JumpSettings s = base::ConfigReader::parse(config, "jump config", read_jump_settings);
  EXPECT_EQ(s.kind, JumpKind::obstacle);
  EXPECT_EQ(s.difficulty_m, 0.3);
  EXPECT_EQ(s.takeoff_features.size(), 3u);
  EXPECT_EQ(s.sim_hz, 600.0);
}

// §3.7's variations reach the World: Mars gravity, a weaker athlete, a heavier body, a cast knee.
TEST(JumpEnv, VariationsChangeTheWorldAndTheBody) {
  const base::Json config = {
      {"gravity_mps2", 3.711}, {"strength", 0.6}, {"mass_scale", 1.2}, {"joint_edits", {{"right_knee", {{"lock", -0.3}}}}}};
  const JumpSettings s = base::ConfigReader::parse(config, "jump config", read_jump_settings);
  JumpEnv env(s), earth(settings());
  EXPECT_EQ(env.world().config().gravity, Eigen::Vector3d(0.0, 0.0, -3.711));
  EXPECT_EQ(env.world().config().strength, 0.6);
  EXPECT_NEAR(env.model().total_mass(), 1.2 * earth.model().total_mass(), 1e-9);
  const int knee = env.model().find_link("right_knee");
  ASSERT_GE(knee, 0);
  EXPECT_TRUE(env.model().links()[std::size_t(knee)].locked);
  // The same take-off state and actions, gravity alone changed: the COM rises faster on Mars.
  JumpSettings mars_settings = settings();
  mars_settings.gravity_mps2 = 3.711;
  JumpEnv mars(mars_settings);
  base::Rng rng(5);
  std::vector<double> obs, earth_obs;
  mars.reset(obs);
  earth.reset(earth_obs);
  learn::StepResult a, b;
  for (int t = 0; t < 3; ++t) {  // 0.15 s: the random actions throw Earth's athlete down by the fifth
    const auto action = random_action(mars.action_space(), rng);
    mars.step(action, a);
    earth.step(action, b);
    ASSERT_FALSE(a.terminated || b.terminated) << "step " << t;
  }
  EXPECT_GT(mars.features().com_vel.z(), earth.features().com_vel.z() + 0.5);
  for (const base::Json& bad : {base::Json{{"joint_edits", {{"tail", {{"lock", 0.0}}}}}},
                                base::Json{{"joint_edits", {{"right_knee", 1.0}}}}, base::Json{{"mass_scale", 0.0}}}) {
    try {
      base::ConfigReader::parse(bad, "jump config", read_jump_settings);
      FAIL() << bad.dump();
    } catch (const base::UserError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.begin().key()), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace podium::tasks::jump
