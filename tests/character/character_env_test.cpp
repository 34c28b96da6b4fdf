// CharacterEnv on humanoid21 and humanoid34: every action map steps, observations have their
// documented sizes, facing-invariant parts are, starts do what they say, state resumes.
#include "podium/character/character_env.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "env_util.h"
#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/observations.h"
#include "podium/character/starts.h"
#include "podium/learn/vec_env.h"
#include "test_util.h"

namespace podium::character {
namespace {

// A standing clip swaying its knees: a reference for residual actions and reference frames.
std::shared_ptr<const Clip> sway_clip(const sim::ModelPtr& model) {
  auto clip = std::make_shared<Clip>();
  clip->model = model;
  const int knee = model->link(model->find_link("knee_right") >= 0 ? "knee_right" : "right_knee").q_index;
  for (int f = 0; f <= 40; ++f) {
    Eigen::VectorXd q = model->standing_pose();
    q(knee) = -0.3 * std::sin(0.2 * f);
    clip->times_s.push_back(f / 40.0);
    clip->poses.push_back(q);
  }
  return clip;
}

std::vector<double> random_action(const learn::BoxSpace& box, base::Rng& rng) {
  std::vector<double> a(box.size());
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = rng.uniform(std::max(box.low[k], -1.0), std::min(box.high[k], 1.0));
  return a;
}

bool finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Every observation part, with the size this test expects from the header's documentation.
void add_every_part(CharacterEnvParts& parts, std::size_t& expected) {
  const auto& m = *parts.model;
  const std::size_t joints = m.nv() - 6, bodies = m.bodies().size();
  parts.observation.push_back(std::make_unique<JointAngles>(parts.model));
  parts.observation.push_back(std::make_unique<JointVelocities>());
  parts.observation.push_back(std::make_unique<HeadHeight>());
  parts.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}));
  parts.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{true, false, false}));
  parts.observation.push_back(std::make_unique<EndEffectors>());
  parts.observation.push_back(std::make_unique<CenterOfMass>());
  parts.observation.push_back(std::make_unique<TorsoAxes>(true));
  parts.observation.push_back(std::make_unique<TorsoAxes>(false));
  parts.observation.push_back(std::make_unique<HeightMap>());
  parts.observation.push_back(std::make_unique<ReferenceFrames>(parts.model, std::vector<int>{1, 5}));
  parts.observation.push_back(std::make_unique<TaskScalars>(
      1, [](const CharacterEnv& env, std::span<double> out) { out[0] = env.world().config().strength; }));
  expected =
      2 * joints + 1 + bodies * 15 + bodies * 3 + 3 * m.end_effector_bodies().size() + 4 + 3 + 9 + 25 + 2 * (joints + 9) + 1;
}

CharacterEnvParts parts_with(const char* model_name, std::unique_ptr<ActionMap> action, std::size_t& expected) {
  CharacterEnvParts parts;
  parts.model = sim::load_shipped_model(model_name);
  parts.episode_steps = 12;
  parts.action = std::move(action);
  parts.reference = sway_clip(parts.model);
  add_every_part(parts, expected);
  parts.start = std::make_unique<ReferenceStart>(0.05, true);
  parts.reward = [](const CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    out.reward = env.features().head_height_m;
    out.terminated = env.features().com.z() < 0.2;
  };
  return parts;
}

TEST(CharacterEnv, StepsHumanoid21WithEveryActionMap) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid21");
  const PoseBridge bridge(model);
  learn::VaeConfig vc;
  vc.latent_size = 4;
  vc.hidden = {16};
  auto vae = std::make_shared<learn::PoseVae>(vc, bridge.lower(), bridge.upper(), 0, 7);  // untrained: any decoder will do
  struct Case {
    const char* name;
    std::unique_ptr<ActionMap> action;
    std::size_t action_size;
  };
  std::vector<Case> cases;
  cases.push_back({"torque", std::make_unique<TorqueActions>(), 21});
  cases.push_back({"pd", std::make_unique<TargetActions>(model, sim::Control::pd), 21});
  cases.push_back({"spd_maba", std::make_unique<TargetActions>(model, sim::Control::spd_maba), 21});
  cases.push_back({"spd_dense", std::make_unique<TargetActions>(model, sim::Control::spd_dense), 21});
  cases.push_back({"vae", std::make_unique<VaeActions>(vae, bridge, sim::Control::spd_maba, 3.0, 0.2), 4 + 21});
  cases.push_back({"residual", std::make_unique<ResidualActions>(model, sim::Control::spd_maba, 0.3), 21});
  for (auto& c : cases) {
    std::size_t expected = 0;
    CharacterEnv env(parts_with("humanoid21", std::move(c.action), expected));
    EXPECT_EQ(env.action_space().size(), c.action_size) << c.name;
    EXPECT_EQ(env.observation_space().size(), expected) << c.name;
    env.seed(3);
    std::vector<double> obs;
    env.reset(obs);
    ASSERT_EQ(obs.size(), expected) << c.name;
    base::Rng rng(4);
    learn::StepResult out;
    int steps = 0;
    for (; steps < 12; ++steps) {
      env.step(random_action(env.action_space(), rng), out);
      ASSERT_EQ(out.observation.size(), expected) << c.name;
      ASSERT_TRUE(finite(out.observation)) << c.name << " step " << steps;
      if (out.terminated || out.truncated) break;
    }
    EXPECT_TRUE(out.terminated || (out.truncated && steps == 11)) << c.name;
    EXPECT_GT(out.reward, 0.0) << c.name;
    std::printf("%-9s %zu actions, %zu observations, %d steps, head %.3f m\n", c.name, env.action_space().size(), obs.size(),
                steps + 1, env.features().head_height_m);
  }
}

TEST(CharacterEnv, TorqueActionsScaleWithStrength) {
  CharacterEnvParts parts = testing::getup_like_parts(5);
  parts.before_episode = [](CharacterEnv& env, base::Rng&) { env.world().set_strength(0.5); };
  CharacterEnv env(std::move(parts));
  std::vector<double> obs;
  env.reset(obs);
  Eigen::VectorXd command;
  TorqueActions().command(env, std::vector<double>(21, 1.0), command);
  const auto& limits = env.model().torque_limits();
  for (int i = 6; i < 27; ++i) EXPECT_DOUBLE_EQ(command(i), 0.5 * limits(i));
  EXPECT_EQ(command.head<6>().norm(), 0.0);
}

// Turning the whole character about the vertical and moving it on flat ground changes none of
// the parts documented as facing-invariant.
TEST(CharacterEnv, FacingInvariantPartsIgnoreHeadingAndPlace) {
  for (const char* name : {"humanoid21", "humanoid34"}) {
    CharacterEnvParts parts;
    parts.model = sim::load_shipped_model(name);
    parts.action = std::make_unique<TorqueActions>();
    parts.observation.push_back(std::make_unique<JointAngles>(parts.model));
    parts.observation.push_back(std::make_unique<JointVelocities>());
    parts.observation.push_back(std::make_unique<RootVelocity>());
    parts.observation.push_back(std::make_unique<HeadHeight>());
    parts.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}));
    parts.observation.push_back(std::make_unique<EndEffectors>());
    parts.observation.push_back(std::make_unique<CenterOfMass>());
    parts.observation.push_back(std::make_unique<TorsoAxes>(true));
    parts.observation.push_back(std::make_unique<TorsoAxes>(false));
    parts.observation.push_back(std::make_unique<HeightMap>());
    parts.start = std::make_unique<RagdollDrop>(testing::short_fall(), RagdollDrop::Lying::any);
    parts.reward = [](const CharacterEnv&, std::span<const double>, learn::StepResult& out) { out.reward = 0; };
    CharacterEnv env(std::move(parts));
    env.seed(9);
    std::vector<double> before, after;
    env.reset(before);  // a fall: moving, turning, touching the ground
    const Eigen::VectorXd q0 = env.world().data().q, qd0 = env.world().data().qd;
    for (double yaw : {1.1, -2.5, std::numbers::pi}) {
      Eigen::VectorXd q = q0;
      const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      q.head<3>() = turn * q0.head<3>() + Eigen::Vector3d(2.0, -3.0, 0.0);
      set_quat(q, 3, Eigen::Quaterniond(turn) * quat_at(q0, 3));
      env.world().set_state(q, qd0);  // root velocities are in the root frame: unchanged
      env.observe(after);
      ASSERT_EQ(after.size(), before.size());
      double worst = 0;
      for (std::size_t k = 0; k < before.size(); ++k) worst = std::max(worst, std::abs(after[k] - before[k]));
      EXPECT_LE(worst, 1e-9) << name << " yaw " << yaw;
    }
  }
}

// World-frame link states (the jumps' global features, thesis §3.4.1) turn with the character:
// positions relative to the root rotate by the turn, and at heading 0 they equal the heading
// frame's values.
TEST(CharacterEnv, WorldFrameLinkStatesTurnWithTheCharacter) {
  CharacterEnvParts parts;
  parts.model = sim::load_shipped_model("humanoid34");
  parts.action = std::make_unique<TorqueActions>();
  parts.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}, LinkStates::Frame::world));
  parts.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}, LinkStates::Frame::heading));
  parts.start = std::make_unique<StandingStart>();
  parts.reward = [](const CharacterEnv&, std::span<const double>, learn::StepResult& out) { out.reward = 0; };
  CharacterEnv env(std::move(parts));
  std::vector<double> obs;
  env.reset(obs);
  const std::size_t half = obs.size() / 2;
  for (std::size_t k = 0; k < half; ++k) EXPECT_NEAR(obs[k], obs[half + k], 1e-12) << "entry " << k;
  Eigen::VectorXd q = env.world().data().q;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  set_quat(q, 3, turn * quat_at(q, 3));
  env.world().set_state(q, env.world().data().qd);
  std::vector<double> turned;
  env.observe(turned);
  const int hand = env.model().find_body("right_hand");  // 15 values per body; position first
  const Eigen::Vector3d before(obs[15 * hand], obs[15 * hand + 1], obs[15 * hand + 2]);
  const Eigen::Vector3d after(turned[15 * hand], turned[15 * hand + 1], turned[15 * hand + 2]);
  EXPECT_LT((after - turn * before).norm(), 1e-9);
  EXPECT_GT((after - before).norm(), 1e-2);  // the hand is beside the root: it moved
}

TEST(CharacterEnv, RagdollDropLandsSupineOrProneWhereAsked) {
  for (auto lying : {RagdollDrop::Lying::supine, RagdollDrop::Lying::prone}) {
    CharacterEnvParts parts = testing::getup_like_parts(5);
    parts.start = std::make_unique<RagdollDrop>(sim::RagdollStart{}, lying, Placement{3.0, -1.0, 0.0});
    CharacterEnv env(std::move(parts));
    std::vector<double> obs;
    int right = 0;
    for (std::uint64_t seed = 0; seed < 5; ++seed) {
      env.seed(seed);
      env.reset(obs);
      const auto& d = env.world().data();
      const Eigen::Vector3d front = d.links[env.model().bodies()[env.model().torso_body()].link].R.col(0);
      const bool supine = front.z() > 0;
      right += supine == (lying == RagdollDrop::Lying::supine);
      EXPECT_NEAR(d.q(0), 3.0, 1.5);  // lands near where it was dropped
      EXPECT_NEAR(d.q(1), -1.0, 1.5);
      EXPECT_LT(env.features().head_height_m, 0.5);
    }
    std::printf("%s: %d of 5 falls land that way\n", lying == RagdollDrop::Lying::supine ? "supine" : "prone", right);
    EXPECT_GE(right, 4);
  }
}

TEST(CharacterEnv, ReferenceAndStateStartsSetTheStateAndClock) {
  std::size_t expected = 0;
  CharacterEnvParts parts = parts_with("humanoid34", std::make_unique<TorqueActions>(), expected);
  const auto clip = parts.reference;
  parts.start = std::make_unique<ReferenceStart>(0.0, false, 0.5);
  CharacterEnv env(std::move(parts));
  std::vector<double> obs;
  env.reset(obs);
  EXPECT_EQ(env.reference_time_s(), 0.5);
  Eigen::VectorXd want = clip->sample(0.5);
  want(2) = env.world().data().q(2);  // may be raised off the ground
  EXPECT_LE(testing::config_distance(env.model(), env.world().data().q, want), 1e-9);
  learn::StepResult out;
  env.step(std::vector<double>(env.action_space().size(), 0.0), out);
  EXPECT_NEAR(env.reference_time_s(), 0.5 + 1.0 / 40.0, 1e-12);

  const Eigen::VectorXd q = env.model().standing_pose();
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(env.model().nv());
  qd(3) = 0.5;  // root ω_x
  const StateStart state(q, qd, 0.25);
  state.begin(env, env.rng());
  EXPECT_LE((env.world().data().q - q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(env.world().data().qd(3), 0.5, 1e-12);
  EXPECT_EQ(env.reference_time_s(), 0.25);
}

// save_state/load_state: a restored copy has the same state, clock and generator stream.
TEST(CharacterEnv, SavedStateResumesInAFreshEnv) {
  CharacterEnv a(testing::getup_like_parts(50));
  CharacterEnv b(testing::getup_like_parts(50));
  a.seed(21);
  std::vector<double> obs_a, obs_b;
  a.reset(obs_a);
  learn::StepResult out;
  for (int k = 0; k < 7; ++k) a.step(std::vector<double>(21, 0.1), out);
  const base::Json state = *a.save_state();
  b.load_state(base::Json::parse(state.dump()));
  b.observe(obs_b);
  a.observe(obs_a);
  EXPECT_EQ(b.step_index(), 7);
  for (std::size_t k = 0; k < obs_a.size(); ++k) EXPECT_NEAR(obs_b[k], obs_a[k], 1e-12);
  // The generators continue alike: the next episode starts from the same fall.
  a.reset(obs_a);
  b.reset(obs_b);
  EXPECT_EQ(obs_a, obs_b);
  EXPECT_THROW(b.load_state(base::Json{{"q", {1, 2}}, {"qd", {1}}}), base::UserError);
}

// Saved mid-episode (with per-episode friction and strength, contacts under way) and loaded into
// a fresh env with a fresh World, the episode continues bitwise: the World snapshot carries
// the contact warm starts that a reset from (q, q̇) would lose.
TEST(CharacterEnv, SavedMidEpisodeReplaysBitwiseInAFreshEnv) {
  const auto parts = [] {
    CharacterEnvParts p = testing::getup_like_parts(60);
    p.before_episode = [](CharacterEnv& env, base::Rng& rng) {
      env.world().set_friction(rng.uniform(0.5, 1.0));
      env.world().set_strength(rng.uniform(0.6, 1.0));
    };
    return p;
  };
  CharacterEnv a(parts());
  a.seed(8);
  std::vector<double> obs;
  a.reset(obs);
  base::Rng actions(3);
  const auto action = [&] {
    std::vector<double> x(a.action_space().size());
    for (double& v : x) v = actions.uniform(-1.0, 1.0);
    return x;
  };
  learn::StepResult out;
  for (int k = 0; k < 20; ++k) a.step(action(), out);
  ASSERT_FALSE(a.features().contacts.empty());
  const std::string saved = a.save_state()->dump();
  std::vector<std::vector<double>> replay;
  std::vector<learn::StepResult> want;
  for (int k = 0; k < 30; ++k) {
    replay.push_back(action());
    a.step(replay.back(), out);
    want.push_back(out);
  }
  CharacterEnv b(parts());
  b.load_state(base::Json::parse(saved));
  EXPECT_EQ(b.world().config().friction, a.world().config().friction);
  for (std::size_t k = 0; k < replay.size(); ++k) {
    b.step(replay[k], out);
    ASSERT_EQ(out.observation, want[k].observation) << "step " << k;
    ASSERT_EQ(out.reward, want[k].reward) << "step " << k;
    ASSERT_EQ(out.terminated, want[k].terminated);
    ASSERT_EQ(out.truncated, want[k].truncated);
  }
  EXPECT_EQ(b.world().data().q, a.world().data().q);
  EXPECT_EQ(b.world().data().qd, a.world().data().qd);
}

// Zero residuals track the reference exactly; the VAE map is the decoder's pose through the
// bridge; the reference frames ahead are the clip's poses at t + k·dt.
TEST(CharacterEnv, ActionMapsAndReferenceFramesReadTheReference) {
  std::size_t expected = 0;
  CharacterEnvParts parts =
      parts_with("humanoid34",
                 std::make_unique<ResidualActions>(sim::load_shipped_model("humanoid34"), sim::Control::spd_maba, 0.3), expected);
  const auto clip = parts.reference;
  parts.start = std::make_unique<ReferenceStart>(0.0, false, 0.2);
  CharacterEnv env(std::move(parts));
  std::vector<double> obs;
  env.reset(obs);
  const PoseBridge bridge(env.world().model_ptr());
  Eigen::VectorXd command;
  ResidualActions(env.world().model_ptr(), sim::Control::spd_maba, 0.3)
      .command(env, std::vector<double>(bridge.size(), 0.0), command);
  const Eigen::VectorXd want = bridge.target(bridge.pose(clip->sample(0.2)));
  EXPECT_LE((command - want).cwiseAbs().maxCoeff(), 1e-12);

  learn::VaeConfig vc;
  vc.latent_size = 3;
  vc.hidden = {8};
  auto vae = std::make_shared<learn::PoseVae>(vc, bridge.lower(), bridge.upper(), 0, 1);
  std::vector<double> action(3 + bridge.size(), 0.05);
  VaeActions(vae, bridge, sim::Control::spd_maba, 3.0, 0.2).command(env, action, command);
  EXPECT_LE((command - bridge.target(learn::pose_action_to_target(*vae, action))).cwiseAbs().maxCoeff(), 1e-12);

  // The ReferenceFrames block sits before the last scalar: 2 × (joints + 9) values.
  const std::size_t joints = env.model().nv() - 6, block = joints + 9;
  const std::size_t at = obs.size() - 1 - 2 * block;
  for (int i = 0; i < 2; ++i) {
    const std::vector<double> ahead = bridge.pose(clip->sample(0.2 + (i == 0 ? 1 : 5) / 40.0));
    for (std::size_t k = 0; k < joints; ++k) EXPECT_NEAR(obs[at + i * block + k], ahead[k], 1e-12) << i << " " << k;
  }
}

// On flat ground every cell of the height map is the root's height; a box under one cell raises
// the ground there by its top.
TEST(CharacterEnv, HeightMapIsTheRootsHeightAboveTheGround) {
  CharacterEnvParts parts = testing::getup_like_parts(5);
  parts.observation.clear();
  parts.observation.push_back(std::make_unique<HeightMap>(0.25));
  parts.start = std::make_unique<StandingStart>(Placement{0.0, 0.0, 0.0});
  sim::BoxProp box;
  box.center = Eigen::Vector3d(0.5, 0.0, 0.05);
  box.half_extents = Eigen::Vector3d(0.05, 0.05, 0.05);
  parts.world.terrain.boxes.push_back(box);
  CharacterEnv env(std::move(parts));
  std::vector<double> obs;
  env.reset(obs);
  const double h = env.world().data().links[0].p.z();
  ASSERT_EQ(obs.size(), 25u);
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b)
      EXPECT_NEAR(obs[a * 5 + b], (a == 4 && b == 2) ? h - 0.1 : h, 1e-12) << a << " " << b;  // (+0.5, 0): the box
}

// The reward is handed the env itself (not a const view), so a task may keep per-episode trackers
// in it: here it moves the reference clock, and the env's next step sees the change.
TEST(CharacterEnv, TheRewardMayChangeTheEnv) {
  CharacterEnvParts parts = testing::getup_like_parts(5);
  std::vector<double> clocks;
  parts.reward = [&clocks](CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    clocks.push_back(env.reference_time_s());
    env.set_reference_time(10.0 * static_cast<double>(env.step_index()));
    out.reward = 0.0;
  };
  CharacterEnv env(std::move(parts));
  std::vector<double> obs;
  env.reset(obs);
  const std::vector<double> zeros(21, 0.0);
  learn::StepResult out;
  env.step(zeros, out);
  env.step(zeros, out);
  ASSERT_EQ(clocks.size(), 2u);
  EXPECT_NEAR(clocks[1], 10.0 * 1 + env.control_dt_s(), 1e-9);  // set after step 1, then one control period on
}

// CharacterEnv inside learn's VecEnv: copies step on worker threads and their rollout state
// (each copy's save_state) round-trips through a fresh VecEnv.
TEST(CharacterEnv, RunsInAVecEnvAndResumesItsRolloutState) {
  const auto make = [] {
    std::vector<std::unique_ptr<learn::Env>> envs;
    for (int i = 0; i < 2; ++i) envs.push_back(std::make_unique<CharacterEnv>(testing::getup_like_parts(6)));
    return std::make_unique<learn::VecEnv>(std::move(envs), 2, 17);
  };
  auto a = make();
  const std::vector<double> zeros(2 * 21, 0.0);
  for (int k = 0; k < 9; ++k) a->step(zeros);  // crosses an episode end (6 steps)
  auto b = make();
  b->load_state(base::Json::parse(a->save_state().dump()));
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(b->observation(i), a->observation(i));
}

TEST(CharacterEnv, RejectsMissingPartsAndWrongActions) {
  CharacterEnvParts parts = testing::getup_like_parts(5);
  parts.start.reset();
  EXPECT_THROW(CharacterEnv{std::move(parts)}, base::UserError);
  CharacterEnv env(testing::getup_like_parts(5));
  std::vector<double> obs;
  env.reset(obs);
  learn::StepResult out;
  EXPECT_THROW(env.step(std::vector<double>(3, 0.0), out), base::UserError);
  std::vector<double> diverged(env.action_space().size(), 0.0);
  diverged[2] = std::numeric_limits<double>::quiet_NaN();
  try {  // a diverged policy fails the trial with the reason
    env.step(diverged, out);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("action 2 is nan, not finite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(TargetActions(env.world().model_ptr(), sim::Control::torque), base::UserError);
}

}  // namespace
}  // namespace podium::character
