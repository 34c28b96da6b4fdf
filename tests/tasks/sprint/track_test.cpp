// The track on real Bullet worlds: the finish time of a box moved at constant speed, a box's
// stopping distance on each runway μ, and the fall and lane rules (sprint seed §2, §3.1).
#include "track.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "podium/base/error.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::sprint {
namespace {

// A 10 kg box (0.4 × 0.4 × 0.1 m) with a 10 g nub on a hinge at its centre (a model needs a joint);
// the box is the root, so the torso the finish line watches.
sim::ModelPtr box_model() {
  const base::Json model = base::Json::parse(R"({
    "name": "box", "standing_root_height": 0.05,
    "bodies": [
      {"name": "box", "mass": 10, "geoms": [{"type": "box", "half_extents": [0.2, 0.2, 0.05]}]},
      {"name": "nub", "parent": "box", "mass": 0.01, "geoms": [{"type": "sphere", "radius": 0.01}],
       "joints": [{"name": "spin", "type": "revolute", "axis": [0, 0, 1], "torque_limit": 1}]}]})");
  return sim::CharacterModel::from_json(model, "box model");
}

sim::WorldConfig sprint_rates() {
  sim::WorldConfig c;
  c.sim_hz = 600.0;
  c.control_hz = 30.0;
  return c;
}

TEST(SprintTrack, CrossingTimeIsLinearWithinTheStep) {
  EXPECT_DOUBLE_EQ(*crossing_time(1.0, 9.0, 1.5, 11.0, 10.0), 1.25);
  EXPECT_FALSE(crossing_time(1.0, 8.0, 1.5, 9.9, 10.0).has_value());
  EXPECT_EQ(*crossing_time(1.0, 10.0, 1.5, 11.0, 10.0), 1.0);  // at the plane already
  EXPECT_EQ(*crossing_time(1.0, 9.0, 1.5, 10.0, 10.0), 1.5);
}

// A box moved at a constant 3 m/s (no gravity, no contact) crosses the plane at (L − x_front)/v,
// judged after every simulation step and interpolated within it, to 1e-6 s; turned about z, its
// front is the corner: 0.2 (cos ψ + sin ψ) ahead of its centre.
TEST(SprintTrack, BoxAtConstantSpeedFinishesAtTheAnalyticTime) {
  const sim::ModelPtr model = box_model();
  TrackSpec track;
  track.length_m = 10.0;
  for (const double yaw : {0.0, 0.4}) {
    sim::WorldConfig config = sprint_rates();
    config.gravity.setZero();
    sim::World world(model, config);
    FinishLine finish(*model, track);
    Eigen::VectorXd q = model->standing_pose();
    q(0) = -0.7123;  // so that the crossing falls between simulation steps
    q(2) = 1.0;
    q.segment<4>(3) << std::cos(yaw / 2), 0, 0, std::sin(yaw / 2);
    const double v = 3.0;
    world.reset(q, Eigen::VectorXd::Zero(model->nv()));
    world.set_state_world(q, Eigen::Vector3d::Zero(), Eigen::Vector3d(v, 0, 0), Eigen::VectorXd::Zero(1));
    const double front = -0.7123 + 0.2 * (std::cos(yaw) + std::sin(yaw));
    finish.reset(world);
    EXPECT_NEAR(finish.front_x(), front, 1e-12);
    world.set_substep_observer([&](sim::World& w) { finish.observe(w); });
    int steps = 0;
    while (!finish.finish_time() && steps++ < 200)
      ASSERT_TRUE(world.control_step(sim::Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
    ASSERT_TRUE(finish.finish_time().has_value());
    const double expected = (track.length_m - front) / v;
    std::printf("yaw %.1f: finish %.12f s, analytic %.12f s (%+.2e s)\n", yaw, *finish.finish_time(), expected,
                *finish.finish_time() - expected);
    EXPECT_NEAR(*finish.finish_time(), expected, 1e-6);
    // Not on a simulation step: the interpolation did the work.
    EXPECT_GT(std::abs(expected * config.sim_hz - std::round(expected * config.sim_hz)), 1e-3);
  }
}

// Sliding along one of its axes (the friction cone is a pyramid) at 3 m/s, the box stops within
// 5% of v²/(2μg) for each runway μ the presets draw from.
TEST(SprintTrack, BoxSlidingAtThreeMetresPerSecondStopsAtTheFrictionDistance) {
  const sim::ModelPtr model = box_model();
  sim::World world(model, sprint_rates());
  const double v0 = 3.0, g = 9.81;
  for (const double mu : {0.8, 1.0, 1.2}) {
    world.set_friction(mu);
    Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
    qd(3) = v0;
    world.reset(model->standing_pose(), qd);
    int steps = 0;
    while (world.data().qd.segment<3>(3).norm() > 1e-6 && steps < 100) {
      ASSERT_TRUE(world.control_step(sim::Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
      ++steps;
    }
    const double distance = world.data().q(0), expected = v0 * v0 / (2 * mu * g);
    std::printf("mu %.1f: slid %.4f m, v²/(2μg) = %.4f m (%+.2f%%)\n", mu, distance, expected, 100 * (distance / expected - 1));
    EXPECT_LT(steps, 100);
    EXPECT_NEAR(distance, expected, 0.05 * expected);
  }
}

TEST(SprintTrack, FallIsAnyBodyButTheFeetOnTheGroundAndTheHandsOnlyBeforeTheFirstStep) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const SprintBodies b = SprintBodies::of(*model);
  const GroundAllowance allowed = b.ground_allowance();
  using Partner = sim::Contact::Partner;
  sim::Observation o;
  o.contacts = {{b.left_foot, Partner::ground, -1}, {b.right_foot, Partner::prop, 0}};
  EXPECT_EQ(fallen_body(o, allowed, true), -1);
  o.contacts.push_back({b.left_hand, Partner::ground, -1});
  EXPECT_EQ(fallen_body(o, allowed, false), -1);  // in the blocks
  EXPECT_EQ(fallen_body(o, allowed, true), b.left_hand);
  const int knee = model->find_body("left_shin");
  o.contacts = {{knee, Partner::prop, 1}, {b.right_hand, Partner::body, b.right_foot}};
  EXPECT_EQ(fallen_body(o, allowed, true), -1);  // props and own bodies are not the ground
  o.contacts.push_back({knee, Partner::ground, 2});
  EXPECT_EQ(fallen_body(o, allowed, false), knee);
}

TEST(SprintTrack, LeavingTheLaneIsACentroidBeyondHalfItsWidth) {
  TrackSpec track;
  EXPECT_FALSE(outside_lane(track, 0.0));
  EXPECT_FALSE(outside_lane(track, -0.61));
  EXPECT_TRUE(outside_lane(track, 0.6101));
  EXPECT_TRUE(outside_lane(track, -0.62));
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const SprintBodies b = SprintBodies::of(*model);
  sim::World world(model, sprint_rates());
  Eigen::VectorXd q = model->standing_pose();
  const std::vector<int> watched = {0, b.left_foot, b.right_foot};
  world.reset(q, Eigen::VectorXd::Zero(model->nv()));
  EXPECT_EQ(body_outside_lane(track, world, watched), -1);
  q(1) = 0.55;  // the left foot (≈ 0.1 m to the left of the root) crosses the line first
  world.set_state(q, Eigen::VectorXd::Zero(model->nv()));
  EXPECT_EQ(body_outside_lane(track, world, watched), b.left_foot);
}

// What the dip finish exploits: pitching the chest forward brings the torso's front (the chest's
// sphere) nearer the line than the upright pose does.
TEST(SprintTrack, LeaningTheChestMovesTheTorsoFrontForward) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  sim::CharacterData data(*model);
  auto front = [&](double lean) {
    data.q = model->standing_pose();
    const Eigen::Quaterniond r(Eigen::AngleAxisd(lean, Eigen::Vector3d::UnitY()));
    data.q.segment<4>(model->link("chest").q_index) << r.w(), r.x(), r.y(), r.z();
    sim::forward_kinematics(*model, data);
    return std::max(body_front_x(*model, data, 0), body_front_x(*model, data, model->torso_body()));
  };
  // Upright, the chest's sphere (r 0.1291 m) is the front.
  EXPECT_NEAR(front(0.0), 0.1291, 1e-12);
  EXPECT_GT(front(0.5), front(0.25));
  EXPECT_GT(front(0.25), front(0.0));
}

TEST(SprintTrack, BodiesAreResolvedByNameOrRefused) {
  EXPECT_THROW(SprintBodies::of(*box_model()), base::UserError);
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const SprintBodies b = SprintBodies::of(*model);
  EXPECT_EQ(model->bodies()[b.right_upper_arm].name, "right_upper_arm");
  const FinishLine finish(*model, TrackSpec{});
  EXPECT_EQ(finish.torso_bodies(), (std::vector<int>{0, model->torso_body()}));
}

}  // namespace
}  // namespace podium::tasks::sprint
