// The sprint environment on humanoid34 (sprint seed §2): what it observes, that its checkpoints
// and hand-over states continue a rollout bitwise, its lane and finish rules, its per-episode
// draw, and the wind's drag on a runner at rest.
#include "sprint_env.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/error.h"

namespace podium::tasks::sprint {
namespace {

EpisodeDraw draw_of(double wind_mps, double friction) {
  EpisodeDraw d;
  d.wind_mps = wind_mps;
  d.friction = friction;
  return d;
}

SprintEnvSettings smoke(std::optional<EpisodeDraw> draw = std::nullopt) {
  SprintEnvSettings s;
  s.preset = load_sprint_preset("smoke");
  s.fixed_draw = draw;
  return s;
}

std::size_t info(const std::string& name) {
  const std::vector<std::string> names = sprint_env_info_names();
  const auto at = std::find(names.begin(), names.end(), name);
  EXPECT_NE(at, names.end()) << name;
  return static_cast<std::size_t>(at - names.begin());
}

// Small random SPD targets about the zero pose, drawn once.
std::vector<std::vector<double>> random_actions(const SprintEnv& env, int count, std::uint64_t seed) {
  base::Rng rng(seed);
  std::vector<std::vector<double>> actions(count, std::vector<double>(env.action_space().size()));
  for (auto& a : actions)
    for (double& v : a) v = rng.uniform(-0.3, 0.3);
  return actions;
}

// The blocks: boxes resting on the ground behind the start line, their top faces inclined by their
// angle and facing the track, in the env's World as props.
TEST(SprintEnv, StartingBlocksAreInclinedPropsBehindTheLine) {
  const std::vector<BlockSpec> specs = default_blocks();
  const std::vector<sim::BoxProp> props = starting_blocks(specs);
  ASSERT_EQ(props.size(), 2u);
  for (std::size_t k = 0; k < props.size(); ++k) {
    const sim::BoxProp& p = props[k];
    const Eigen::Matrix3d R = p.rotation.toRotationMatrix();
    double lowest = 1e9;
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0})
        for (const double sz : {-1.0, 1.0})
          lowest = std::min(lowest, (p.center + R * p.half_extents.cwiseProduct(Eigen::Vector3d(sx, sy, sz))).z());
    EXPECT_NEAR(lowest, 0.0, 1e-12) << p.name;
    const Eigen::Vector3d normal = R.col(2);
    EXPECT_NEAR(std::acos(normal.z()), specs[k].angle_rad, 1e-12) << p.name;
    EXPECT_GT(normal.x(), 0.0) << p.name;  // facing the runner ahead of it
    EXPECT_LT(p.center.x() + p.half_extents.norm(), 0.0) << p.name;
  }
  SprintEnv env(smoke());
  EXPECT_EQ(env.world().terrain().config().boxes.size(), 2u);
  EXPECT_GT(env.world().terrain().height(specs[0].x_m, specs[0].y_m), 0.0);
  BlockSpec bad = specs[0];
  bad.angle_rad = 2.0;
  EXPECT_THROW(starting_blocks({bad}), base::UserError);
}

TEST(SprintEnv, ObservationIsTheSeedsStateAndIgnoresWindAndFriction) {
  SprintEnv headwind(smoke(draw_of(-2.0, 0.8))), tailwind(smoke(draw_of(2.0, 1.2)));
  const std::size_t bodies = headwind.model().bodies().size();
  // Link states (15 per body), the COM (3 + 4), the track (3), z (1).
  EXPECT_EQ(headwind.observation_space().size(), 15 * bodies + 3 + 4 + 3 + 1);
  EXPECT_EQ(headwind.action_space().size(), static_cast<std::size_t>(headwind.model().nv() - 6));
  EXPECT_EQ(headwind.episode_steps(), 240);  // the smoke preset's 8 s at 30 Hz
  headwind.seed(1);
  tailwind.seed(1);
  std::vector<double> a, b;
  headwind.reset(a);
  tailwind.reset(b);
  ASSERT_EQ(a.size(), headwind.observation_space().size());
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.back(), 0.0);  // z: no step yet
  // The draws did apply: the runway's μ and the drag at rest, ½ρ(C_dA)_b|w|w on each body.
  EXPECT_EQ(headwind.world().config().friction, 0.8);
  EXPECT_EQ(tailwind.world().config().friction, 1.2);
  EXPECT_LT(headwind.world().external_force(0).x(), 0.0);
  EXPECT_GT(tailwind.world().external_force(0).x(), 0.0);
}

TEST(SprintEnv, RestoredStateReproducesTheRolloutBitwise) {
  SprintEnv env(smoke());
  env.seed(11);
  std::vector<double> observation;
  env.reset(observation);
  learn::StepResult r;
  for (const auto& a : random_actions(env, 5, 4)) env.step(a, r);
  const base::Json saved = *env.save_state();
  const std::vector<std::vector<double>> actions = random_actions(env, 20, 5);
  std::vector<learn::StepResult> original;
  for (const auto& a : actions) {
    env.step(a, r);
    original.push_back(r);
  }
  SprintEnv copy(smoke());  // another env, through the state's text
  copy.load_state(base::Json::parse(saved.dump()));
  EXPECT_EQ(copy.draw().to_json(), env.draw().to_json());
  for (std::size_t k = 0; k < actions.size(); ++k) {
    copy.step(actions[k], r);
    EXPECT_EQ(r.observation, original[k].observation) << "step " << k;
    EXPECT_EQ(r.reward, original[k].reward) << "step " << k;
    EXPECT_EQ(r.info, original[k].info) << "step " << k;
    EXPECT_EQ(r.terminated, original[k].terminated) << "step " << k;
    EXPECT_EQ(r.truncated, original[k].truncated) << "step " << k;
  }
  EXPECT_TRUE(copy.world().data().q == env.world().data().q);
  EXPECT_TRUE(copy.world().data().qd == env.world().data().qd);
  EXPECT_EQ(copy.episode_record(), env.episode_record());
  EXPECT_THROW(copy.load_state(base::Json::object()), base::UserError);
}

// Stage 2 starts at the Start phase's states: an env started at a hand-over state continues the
// World's motion bitwise, on the same clock, with the recorded draw and step count.
TEST(SprintEnv, HandoverStateContinuesTheRolloutBitwise) {
  SprintEnv env(smoke());
  env.seed(3);
  std::vector<double> observation;
  env.reset(observation);
  learn::StepResult r;
  for (const auto& a : random_actions(env, 4, 6)) env.step(a, r);
  const base::Json handover = base::Json::parse(env.handover_state().dump());
  const std::vector<double> at_handover = r.observation;
  const double time_s = env.world().time_s();
  const std::vector<std::vector<double>> actions = random_actions(env, 10, 7);
  std::vector<std::vector<double>> original;
  for (const auto& a : actions) {
    env.step(a, r);
    original.push_back(r.observation);
  }
  SprintEnvSettings s = smoke();
  s.handover_states = {handover};
  SprintEnv stage2(s);
  stage2.seed(99);
  stage2.reset(observation);
  EXPECT_EQ(stage2.draw().to_json(), env.draw().to_json());
  EXPECT_EQ(stage2.world().time_s(), time_s);
  EXPECT_EQ(observation, at_handover);
  for (std::size_t k = 0; k < actions.size(); ++k) {
    stage2.step(actions[k], r);
    EXPECT_EQ(r.observation, original[k]) << "step " << k;
  }
  EXPECT_TRUE(stage2.world().data().q == env.world().data().q);
}

// Pushed sideways at 2 m/s on a frictionless runway (so that it slides rather than tips), the
// runner ends its episode by the lane rule at the first control step at which the root's or a
// foot's centroid is beyond w/2.
TEST(SprintEnv, PushedSidewaysTheEpisodeEndsByTheLaneRule) {
  SprintEnv env(smoke(draw_of(0.0, 0.0)));
  env.seed(2);
  std::vector<double> observation;
  env.reset(observation);
  const int joints = env.model().nv() - 6;
  env.world().set_state_world(env.world().data().q, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 2.0, 0.0),
                              Eigen::VectorXd::Zero(joints));
  const double half = 0.5 * env.settings().preset.track.lane_width_m;
  const std::vector<int> lane_bodies{0, env.bodies().left_foot, env.bodies().right_foot};
  auto widest = [&] {
    double y = 0.0;
    for (const int b : lane_bodies) y = std::max(y, std::abs(env.world().body_centroid(b).y()));
    return y;
  };
  const std::vector<double> zero(env.action_space().size(), 0.0);
  learn::StepResult r;
  double before = widest();
  int steps = 0;
  while (steps < 60) {
    before = widest();
    env.step(zero, r);
    ++steps;
    if (r.terminated || r.truncated) break;
  }
  ASSERT_TRUE(r.terminated);
  EXPECT_EQ(env.outcome(), SprintEnv::Outcome::left_lane);
  EXPECT_EQ(r.info[info("left_lane")], 1.0);
  EXPECT_EQ(r.info[info("fell")], 0.0);
  EXPECT_LE(before, half);
  EXPECT_GT(widest(), half);
  EXPECT_LT(r.info[info("lateral")], 0.0);  // r_d: the offset's penalty
  std::printf("pushed at 2 m/s: out of the lane after %d control steps (widest centroid %.3f m)\n", steps, widest());
}

TEST(SprintEnv, EpisodeRecordsItsDraw) {
  const SprintEnvSettings settings = smoke();
  SprintEnv env(settings);
  std::vector<double> observation;
  learn::StepResult r;
  const std::vector<double> zero(env.action_space().size(), 0.0);
  std::vector<base::Json> draws;
  for (const std::uint64_t seed : {1u, 2u}) {
    env.seed(seed);
    env.reset(observation);
    const EpisodeDraw d = env.draw();
    base::Rng rng(seed);  // the episode's first use of its generator
    EXPECT_EQ(d.to_json(), draw_episode(settings.preset, rng).to_json());
    EXPECT_GE(d.wind_mps, settings.preset.wind_mps.lo);
    EXPECT_LE(d.wind_mps, settings.preset.wind_mps.hi);
    EXPECT_EQ(env.world().config().friction, d.friction);
    EXPECT_EQ(env.episode_record().at("draw"), d.to_json());
    EXPECT_EQ(env.handover_state().at("draw"), d.to_json());
    env.step(zero, r);
    EXPECT_EQ(r.info[info("wind_mps")], d.wind_mps);
    EXPECT_EQ(r.info[info("friction")], d.friction);
    draws.push_back(d.to_json());
  }
  EXPECT_NE(draws[0], draws[1]);
}

// On a frictionless runway nothing horizontal acts on the runner but the drag: at rest in a wind
// w, F = ½ρC_dA|w|w along +x in all (0.6 N at 2 m/s), so after t the COM has moved ½(F/m)t² more
// than in calm air (the runner's own speed, a few mm/s, changes F by under 1%), and the root with it.
TEST(SprintEnv, DragMovesTheRunnerAsTheFormulaSays) {
  const int steps = 15;
  double com[3], root[3];
  const double winds[3] = {-2.0, 0.0, 2.0};
  double mass = 0.0;
  for (int k = 0; k < 3; ++k) {
    SprintEnv env(smoke(draw_of(winds[k], 0.0)));
    env.seed(1);
    std::vector<double> observation;
    env.reset(observation);
    mass = env.model().total_mass();
    const double com0 = env.features().com.x(), root0 = env.world().data().q(0);
    const std::vector<double> zero(env.action_space().size(), 0.0);
    learn::StepResult r;
    for (int s = 0; s < steps; ++s) env.step(zero, r);
    com[k] = env.features().com.x() - com0;
    root[k] = env.world().data().q(0) - root0;
  }
  const double t = steps / 30.0, force = 0.5 * 1.2 * 0.25 * 2.0 * 2.0;
  const double expected = 0.5 * force / mass * t * t;
  std::printf("after %.2f s at rest: COM moved %+.4e (head), %+.4e (calm), %+.4e (tail) m; ½(F/m)t² = %.4e m\n", t, com[0],
              com[1], com[2], expected);
  EXPECT_NEAR(com[2] - com[1], expected, 0.05 * expected);
  EXPECT_NEAR(com[0] - com[1], -expected, 0.05 * expected);
  EXPECT_GT(root[2], root[1]);
  EXPECT_LT(root[0], root[1]);
}

// Standing just behind the finish plane and slid forward at 2 m/s (frictionless, calm), the
// runner finishes when its torso's front reaches the plane, (L − front)/v after the start, and the
// episode ends there. To 2 ms: the body's own settling moves its front a little (the interpolation
// itself is checked to 1e-6 s on a rigid box in track_test.cpp).
TEST(SprintEnv, FinishEndsTheEpisodeAtTheInterpolatedTime) {
  SprintEnvSettings s = smoke(draw_of(0.0, 0.0));
  s.standing.x_m = s.preset.track.length_m - 0.4;
  SprintEnv env(s);
  env.seed(4);
  std::vector<double> observation;
  env.reset(observation);
  const double front = env.finish_line().front_x(), v = 2.0;
  env.world().set_state_world(env.world().data().q, Eigen::Vector3d::Zero(), Eigen::Vector3d(v, 0.0, 0.0),
                              Eigen::VectorXd::Zero(env.model().nv() - 6));
  const std::vector<double> zero(env.action_space().size(), 0.0);
  learn::StepResult r;
  for (int k = 0; k < 30 && !r.terminated && !r.truncated; ++k) env.step(zero, r);
  ASSERT_TRUE(r.truncated);  // the line is a hand-over, not a terminal state: PPO bootstraps there
  EXPECT_FALSE(r.terminated);
  EXPECT_EQ(env.outcome(), SprintEnv::Outcome::finished);
  const double expected = (s.preset.track.length_m - front) / v;
  EXPECT_NEAR(r.info[info("finish_time_s")], expected, 2e-3);
  EXPECT_EQ(env.episode_record().at("finish_time_s").get<double>(), r.info[info("finish_time_s")]);
  std::printf("finish at %.6f s; (L − front)/v = %.6f s\n", r.info[info("finish_time_s")], expected);
}

}  // namespace
}  // namespace podium::tasks::sprint
