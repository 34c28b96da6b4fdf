// Contacts by partner, props and terrain changed between episodes, friction, external forces,
// spherical limits, locked joints, removed limbs and snapshots, on real Bullet worlds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "podium/base/error.h"
#include "podium/sim/starts.h"
#include "podium/sim/world.h"

namespace podium::sim {
namespace {

using Partner = Contact::Partner;

// A 10 kg box (0.4 × 0.4 × 0.1 m) with a 10 g nub on a hinge at its centre (a model needs a joint).
ModelPtr box_model() {
  const base::Json model = base::Json::parse(R"({
    "name": "box", "standing_root_height": 0.05,
    "bodies": [
      {"name": "box", "mass": 10, "geoms": [{"type": "box", "half_extents": [0.2, 0.2, 0.05]}]},
      {"name": "nub", "parent": "box", "mass": 0.01, "geoms": [{"type": "sphere", "radius": 0.01}],
       "joints": [{"name": "spin", "type": "revolute", "axis": [0, 0, 1], "torque_limit": 1}]}]})");
  return CharacterModel::from_json(model, "box model");
}

BoxProp box(const std::string& name, const Eigen::Vector3d& center, const Eigen::Vector3d& half) {
  return {name, center, half, Eigen::Quaterniond::Identity(), 1.0, ""};
}

// A drop from 1.5 m in a random pose under stable PD towards random poses (new ones every
// 0.25 s) for `seconds`: a ragdoll-like episode with impacts, joint limits and contacts.
StepReport spd_drop(World& world, base::Rng& rng, double seconds) {
  const CharacterModel& m = world.model();
  Eigen::VectorXd q = random_pose(m, rng, 1.5);
  CharacterData scratch(m);
  scratch.q = q;
  forward_kinematics(m, scratch);
  q(2) += std::max(0.0, 0.05 - (lowest_geom_point(m, scratch) - world.terrain().height(q(0), q(1))));
  world.reset(q, Eigen::VectorXd::Zero(m.nv()));
  Eigen::VectorXd target = m.standing_pose();
  StepReport r;
  const int steps = static_cast<int>(seconds * world.config().control_hz),
            every = static_cast<int>(0.25 * world.config().control_hz);
  for (int k = 0; k < steps && r.ok; ++k) {
    if (k % every == 0) target = random_pose(m, rng, 0.0, 0.8);
    r = world.control_step(Control::spd_maba, target);
  }
  return r;
}

// The angle between a spherical joint's twist axis and its image, and the twist about it.
std::pair<double, double> swing_twist(const Link& l, const Eigen::VectorXd& q) {
  Eigen::Quaterniond r(q(l.q_index), q(l.q_index + 1), q(l.q_index + 2), q(l.q_index + 3));
  if (r.w() < 0) r.coeffs() = -r.coeffs();
  const double swing = std::acos(std::clamp(l.axis.dot(r * l.axis), -1.0, 1.0));
  return {swing, 2.0 * std::atan2(r.vec().dot(l.axis), r.w())};
}

TEST(WorldContacts, HandOnABoxReportsTheBoxNotTheGround) {
  const ModelPtr model = load_shipped_model("humanoid34");
  Eigen::VectorXd q = model->standing_pose();
  const Link& shoulder = model->link("right_shoulder");
  const Eigen::Quaterniond forward(Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitY()));  // arm straight ahead
  q.segment<4>(shoulder.q_index) << forward.w(), forward.x(), forward.y(), forward.z();
  CharacterData pose(*model);
  pose.q = q;
  forward_kinematics(*model, pose);
  const int hand = model->find_body("right_hand"), head = model->find_body("head");
  const Eigen::Vector3d p = body_point(*model, pose, hand, Eigen::Vector3d::Zero());
  ASSERT_GT(p.x(), 0.4);  // in front of the body
  // A 10 cm column under the hand, the hand's sphere (radius 0.047 m) 0.5 mm into its top, as
  // resting contacts settle (Bullet reports sphere–box points only once they touch).
  const double top = p.z() - 0.047 + 0.0005;
  WorldConfig config;
  config.terrain.boxes = {box("far", Eigen::Vector3d(5, 5, 0.5), Eigen::Vector3d(0.5, 0.5, 0.5)),
                          box("column", Eigen::Vector3d(p.x(), p.y(), top / 2), Eigen::Vector3d(0.05, 0.05, top / 2))};
  World world(model, config);
  world.set_state(q, Eigen::VectorXd::Zero(model->nv()));
  const Observation o = world.observe();
  EXPECT_TRUE(o.touches(hand, Partner::prop, 1));
  EXPECT_FALSE(o.touches(hand, Partner::prop, 0));
  EXPECT_FALSE(o.touches(hand, Partner::ground));
  EXPECT_TRUE(o.touches(model->find_body("right_foot"), Partner::ground, -1));
  EXPECT_FALSE(o.touches(model->find_body("right_foot"), Partner::prop));
  EXPECT_FALSE(o.touches(model->find_body("right_forearm"), Partner::prop));  // same link as the hand: reported per body
  EXPECT_NEAR(world.prop_distance(hand, 1), -0.0005, 2e-4);
  // The head's sphere to the far box's nearest face, 2.5 m ahead at head height.
  TerrainConfig ahead = world.terrain().config();
  ahead.boxes[0].center = Eigen::Vector3d(3.0, 0.0, 1.5);
  world.set_terrain(ahead);
  const Link& head_link = model->links()[model->bodies()[head].link];
  const Geom& skull = head_link.geoms.front();
  const Eigen::Vector3d c =
      world.data().links[model->bodies()[head].link].p + world.data().links[model->bodies()[head].link].R * skull.pos;
  EXPECT_NEAR(world.prop_distance(head, 0), 2.5 - c.x() - skull.radius, 1e-6);
  EXPECT_GT(world.prop_distance(head, 1), 0.3);
}

// Contacts between bodies name the other body, both ways; a ragdoll on a mat touches the mat and the ground.
TEST(WorldContacts, BodyContactsNameTheOtherBodyBothWays) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  config.terrain.boxes = {box("mat", Eigen::Vector3d(0.6, 0, 0.1), Eigen::Vector3d(0.5, 1.0, 0.1))};
  World world(model, config);
  bool body_pair = false, prop = false, ground = false;
  for (int seed = 0; seed < 6; ++seed) {
    base::Rng rng(static_cast<std::uint64_t>(seed));
    ASSERT_TRUE(spd_drop(world, rng, 2.0).ok);
    const Observation o = world.observe();
    for (const Contact& c : o.contacts) {
      EXPECT_TRUE(o.body_contacts[c.body]);
      if (c.partner == Partner::body) {
        body_pair = true;
        EXPECT_NE(c.body, c.index);
        EXPECT_TRUE(o.touches(c.index, Partner::body, c.body)) << c.body << " touches " << c.index << " but not the reverse";
      }
      prop |= c.partner == Partner::prop;
      ground |= c.partner == Partner::ground;
    }
  }
  EXPECT_TRUE(body_pair && prop && ground);
}

// A bar-height curriculum: the mat is raised, then removed, between episodes of one World.
TEST(WorldProps, MovedResizedAddedRemovedBetweenEpisodes) {
  const ModelPtr model = load_shipped_model("humanoid21");
  WorldConfig config;
  config.terrain.boxes = {box("mat", Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(2.0, 2.0, 0.15))};
  World world(model, config);
  auto drop = [&](int seed) {
    base::Rng rng(static_cast<std::uint64_t>(seed));
    RagdollStart start;
    start.drop_height_m = 2.0;
    EXPECT_TRUE(ragdoll_start(world, rng, start).ok);
    return lowest_geom_point(*model, world.data());
  };
  EXPECT_NEAR(drop(1), 0.3, 0.04);
  TerrainConfig raised = world.terrain().config();
  raised.boxes[0].center.z() = 0.25;
  raised.boxes[0].half_extents.z() = 0.25;
  raised.boxes.push_back(box("wall", Eigen::Vector3d(6, 0, 1), Eigen::Vector3d(0.1, 2, 1)));
  world.set_terrain(raised);
  EXPECT_EQ(world.terrain().config().boxes.size(), 2u);
  EXPECT_NEAR(drop(1), 0.5, 0.04);
  TerrainConfig removed;
  world.set_terrain(removed);
  EXPECT_NEAR(drop(1), 0.0, 0.03);
  TerrainConfig bad = raised;
  bad.boxes[1].half_extents.x() = -1;
  EXPECT_THROW(world.set_terrain(bad), base::UserError);
  EXPECT_TRUE(world.terrain().config().boxes.empty());  // unchanged
}

// Rough tiles with heights of either sign: a ragdoll rests on them, in the pits as on the bumps.
TEST(WorldTerrain, RagdollRestsOnTilesOfEitherSign) {
  const ModelPtr model = load_shipped_model("humanoid21");
  WorldConfig config;
  TerrainRegion tiles;
  tiles.kind = TerrainRegion::Kind::rough;
  tiles.min = {-3, -3};
  tiles.max = {3, 3};
  tiles.tile_size_m = 0.5;
  tiles.min_tile_height_m = -0.15;
  tiles.max_tile_height_m = 0.15;
  tiles.seed = 9;
  config.terrain.regions.push_back(tiles);
  World world(model, config);
  base::Rng rng(5);
  ASSERT_TRUE(ragdoll_start(world, rng).ok);
  double gap = 1e9, lowest = 1e9;
  for (std::size_t b = 0; b < model->bodies().size(); ++b) {
    const Eigen::Vector3d p = body_point(*model, world.data(), static_cast<int>(b), Eigen::Vector3d::Zero());
    gap = std::min(gap, p.z() - world.terrain().height(p.x(), p.y()));
    lowest = std::min(lowest, p.z());
  }
  EXPECT_GT(gap, -0.02);
  EXPECT_LT(world.observe().head_height_m, 0.5);
  bool on_tiles = false;
  for (const Contact& c : world.observe().contacts) on_tiles |= c.partner == Partner::ground && c.index == 0;
  EXPECT_TRUE(on_tiles);
  std::printf("lowest body origin %.3f m, least gap to the tiles below %.3f m\n", lowest, gap);
}

// A box set on a 10° slope region rests on its surface where μ > tan 10° and slides down where
// μ < tan 10°; on a flat region 0.3 m up it rests at 0.3 m.
TEST(WorldTerrain, SlopeAndFlatRegionsCarryABox) {
  const ModelPtr model = box_model();
  WorldConfig config;
  TerrainRegion slope, flat;
  slope.kind = TerrainRegion::Kind::slope;
  slope.min = {-2, -2};
  slope.max = {2, 2};
  slope.slope_rad = 10.0 * std::numbers::pi / 180;
  flat.min = {3, -1};
  flat.max = {5, 1};
  flat.height_m = 0.3;
  config.terrain.regions = {slope, flat};
  World world(model, config);
  auto settle = [&](double x, double mu) {
    world.set_friction(mu);
    Eigen::VectorXd q = model->standing_pose();
    const double tilt = slope.slope_rad * (x < 2);
    q(0) = x;
    q(2) = world.terrain().height(x, 0) + 0.05 / std::cos(tilt) + 0.002;
    q.segment<4>(3) << std::cos(-tilt / 2), 0, std::sin(-tilt / 2), 0;  // flat on the surface
    world.reset(q, Eigen::VectorXd::Zero(model->nv()));
    for (int k = 0; k < 40; ++k) EXPECT_TRUE(world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
    return world.data().q;
  };
  const Eigen::VectorXd holds = settle(0.0, 1.0);
  EXPECT_NEAR(holds(0), 0.0, 0.01);
  EXPECT_NEAR(holds(2), 2 * std::tan(slope.slope_rad) + 0.05 / std::cos(slope.slope_rad), 0.01);  // the surface 2 m up the slope
  const Eigen::VectorXd slides = settle(0.0, 0.1);
  EXPECT_LT(slides(0), -0.05);
  const Eigen::VectorXd raised = settle(4.0, 1.0);
  EXPECT_NEAR(raised(2), 0.35, 0.01);
}

// Sliding box: stopping distance v²/(2μg) for each episode's μ, within 5%.
TEST(WorldFriction, ChangedBetweenEpisodesGivesTheStoppingDistance) {
  const ModelPtr model = box_model();
  World world(model, WorldConfig{});
  const double v0 = 2.0, g = 9.81;
  for (const double mu : {0.5, 0.25, 0.8}) {
    world.set_friction(mu);
    Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
    qd(3) = v0;
    world.reset(model->standing_pose(), qd);
    int steps = 0;
    while (world.data().qd.segment<3>(3).norm() > 1e-6 && steps < 200) {
      ASSERT_TRUE(world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
      ++steps;
    }
    const double distance = world.data().q(0), expected = v0 * v0 / (2 * mu * g);
    std::printf("mu %.2f: slid %.4f m, v²/(2μg) = %.4f m (%+.2f%%)\n", mu, distance, expected, 100 * (distance / expected - 1));
    EXPECT_LT(steps, 200);
    EXPECT_NEAR(distance, expected, 0.05 * expected);
  }
}

// F = ½ ρ C_d A |v_rel| v_rel on the box (A: its faces projected across the wind), and applied:
// one step changes the linear momentum by Σ F Δt in every control mode.
TEST(WorldForces, WindForceIsTheDragFormulaAndActsInEveryControlMode) {
  const ModelPtr model = box_model();
  WorldConfig config;
  config.gravity.setZero();
  World world(model, config);
  Eigen::VectorXd q = model->standing_pose();
  q(2) = 1.0;
  const double yaw = 0.5;
  q.segment<4>(3) << std::cos(yaw / 2), 0, 0, std::sin(yaw / 2);
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
  world.set_state_world(q, Eigen::Vector3d::Zero(), Eigen::Vector3d(3, 0, 0), Eigen::VectorXd::Zero(1));
  Wind wind;
  wind.velocity = Eigen::Vector3d(10, 0, 0);
  // Relative wind 7 m/s along x, on a box turned 0.5 rad about z: faces 0.4 × 0.1 m seen at cos and sin.
  const double area = 0.4 * 0.1 * (std::cos(yaw) + std::sin(yaw));
  const Eigen::Vector3d expected = 0.5 * 1.2 * 1.0 * area * 7.0 * Eigen::Vector3d(7.0, 0, 0);
  EXPECT_LE((world.wind_force(0, wind) - expected).norm(), 1e-12 * expected.norm()) << world.wind_force(0, wind).transpose();
  EXPECT_NEAR(world.body_centroid_velocity(0).x(), 3.0, 1e-12);
  for (const Control mode : {Control::torque, Control::pd, Control::spd_dense, Control::spd_maba}) {
    world.set_state_world(q, Eigen::Vector3d::Zero(), Eigen::Vector3d(3, 0, 0), Eigen::VectorXd::Zero(1));
    world.apply_wind(wind);
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (int b = 0; b < 2; ++b) total += world.external_force(b);
    CharacterData before = world.data();
    Eigen::Vector3d com, v_before, v_after;
    center_of_mass(*model, before, com, v_before);
    const Eigen::VectorXd command = mode == Control::torque ? Eigen::VectorXd::Zero(model->nv()) : world.data().q;
    ASSERT_TRUE(world.sim_step(mode, command).ok);
    CharacterData after = world.data();
    center_of_mass(*model, after, com, v_after);
    const Eigen::Vector3d impulse = model->total_mass() * (v_after - v_before);
    EXPECT_LE((impulse - total * world.dt_s()).norm(), 1e-9 * total.norm() * world.dt_s()) << "mode " << static_cast<int>(mode);
  }
  world.set_external_force(0, Eigen::Vector3d::Zero());
  world.set_external_force(1, Eigen::Vector3d::Zero());
  EXPECT_THROW(world.set_external_force(2, Eigen::Vector3d::UnitX()), base::UserError);
}

// A shoulder driven hard past its 0.6 rad swing cone and ±0.3 rad twist stops at them.
TEST(WorldJoints, SphericalJointStopsAtItsConeAndTwistRange) {
  const ModelPtr model = load_shipped_model("humanoid34");
  auto drive = [&](bool limited) {
    WorldConfig config;
    config.gravity.setZero();
    config.self_collision = false;
    config.torque_limits = false;
    if (limited)
      config.edits.joints = {{"right_shoulder", base::Json{{"axis", {0, 0, -1}}, {"swing", 0.6}, {"twist", {-0.3, 0.3}}}}};
    World world(model, config);
    Eigen::VectorXd q = world.model().standing_pose();
    q(2) = 3.0;
    world.reset(q, Eigen::VectorXd::Zero(world.model().nv()));
    const Link& l = world.model().link("right_shoulder");
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(world.model().nv());
    tau.segment<3>(l.v_index) << 40.0, 0.0, 15.0;  // swing about x, twist about the arm
    double swing = 0, twist = 0;
    for (int k = 0; k < 1600 && (limited || swing < 1.2 || twist < 0.6); ++k) {  // an unlimited arm spins on and diverges
      EXPECT_TRUE(world.sim_step(Control::torque, tau).ok);
      const auto [s, t] = swing_twist(l, world.data().q);
      swing = std::max(swing, s), twist = std::max(twist, std::abs(t));
    }
    return std::pair{swing, twist};
  };
  const auto [swing, twist] = drive(true);
  const auto [free_swing, free_twist] = drive(false);
  std::printf(
      "2 s of shoulder torque: largest swing %.4f rad (cone 0.6; unlimited: past %.2f), twist %.4f rad (range ±0.3; unlimited: "
      "past %.2f)\n",
      swing, free_swing, twist, free_twist);
  EXPECT_GT(free_swing, 1.2);
  EXPECT_GT(free_twist, 0.6);
  EXPECT_LT(swing, 0.6 + 0.01);
  EXPECT_GT(swing, 0.6 - 0.01);
  EXPECT_LT(twist, 0.3 + 0.01);
  EXPECT_GT(twist, 0.3 - 0.01);
}

// A cast: the elbow locked at 1.2 rad keeps it through a drop under gravity and impacts, with
// PD targets for it all over its range; the unlocked elbow follows them.
TEST(WorldJoints, LockedElbowKeepsItsAngleUnderGravityAndImpacts) {
  const ModelPtr model = load_shipped_model("humanoid34");
  auto worst = [&](bool locked) {
    WorldConfig config;
    if (locked) config.edits.joints = {{"right_elbow", base::Json{{"lock", 1.2}}}};
    World world(model, config);
    const CharacterModel& m = world.model();
    const Link& elbow = m.link("right_elbow");
    base::Rng rng(11);
    Eigen::VectorXd q = random_pose(m, rng, 1.5, 0.5);
    q(elbow.q_index) = 1.2;
    world.reset(q, Eigen::VectorXd::Zero(m.nv()));
    double error = 0;
    Eigen::VectorXd target = m.standing_pose();
    for (int k = 0; k < 80; ++k) {  // 2 s: the fall, the impact, rolling
      if (k % 10 == 0) target = random_pose(m, rng, 0.0, 0.8);
      for (int s = 0; s < world.substeps(); ++s) {
        EXPECT_TRUE(world.sim_step(Control::spd_maba, target).ok);
        error = std::max(error, std::abs(world.data().q(elbow.q_index) - 1.2));
      }
    }
    return error;
  };
  const double locked = worst(true), free = worst(false);
  std::printf("elbow: largest deviation from 1.2 rad over 2 s, locked %.2e rad, unlocked %.3f rad\n", locked, free);
  EXPECT_LT(locked, 0.01);
  EXPECT_GT(free, 0.2);
}

// A spherical joint locked at a rotation stays there under hard torques on it and its neighbours.
TEST(WorldJoints, LockedShoulderKeepsItsRotation) {
  const ModelPtr model = load_shipped_model("humanoid34");
  const Eigen::Quaterniond lock(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 0).normalized()));
  WorldConfig config;
  config.gravity.setZero();
  config.self_collision = false;
  config.edits.joints = {{"right_shoulder", base::Json{{"lock", {lock.w(), lock.x(), lock.y(), lock.z()}}}}};
  World world(model, config);
  const CharacterModel& m = world.model();
  const Link& shoulder = m.link("right_shoulder");
  Eigen::VectorXd q = m.standing_pose();
  q(2) = 3.0;
  q.segment<4>(shoulder.q_index) << lock.w(), lock.x(), lock.y(), lock.z();
  world.reset(q, Eigen::VectorXd::Zero(m.nv()));
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(m.nv());
  tau.segment<3>(shoulder.v_index) << 60, -40, 30;
  tau(m.link("right_elbow").v_index) = 30;
  double worst = 0;
  for (int k = 0; k < 800; ++k) {
    ASSERT_TRUE(world.sim_step(Control::torque, tau).ok);
    const Eigen::VectorXd& x = world.data().q;
    const Eigen::Quaterniond now(x(shoulder.q_index), x(shoulder.q_index + 1), x(shoulder.q_index + 2), x(shoulder.q_index + 3));
    worst = std::max(worst, now.angularDistance(lock));
  }
  EXPECT_LT(worst, 0.01);
}

TEST(WorldJoints, LimbRemovedWithItsSubtree) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  config.edits.remove = {"left_forearm"};
  World world(model, config);
  const CharacterModel& m = world.model();
  EXPECT_EQ(m.bodies().size(), model->bodies().size() - 2);  // forearm and hand
  EXPECT_EQ(m.nv(), model->nv() - 1);                        // the elbow
  EXPECT_EQ(m.find_body("left_hand"), -1);
  EXPECT_EQ(m.end_effector_bodies().size(), 3u);
  EXPECT_LT(m.total_mass(), model->total_mass() - 1.9);
  base::Rng rng(3);
  EXPECT_TRUE(spd_drop(world, rng, 2.0).ok);
  // The same from the model file's own keys; bad names are refused with what is wrong.
  base::Json file = model->source();
  file["remove"] = {"right_upper_arm"};
  EXPECT_EQ(CharacterModel::from_json(file, "test")->bodies().size(), model->bodies().size() - 3);
  file["remove"] = {"tail"};
  EXPECT_THROW(CharacterModel::from_json(file, "test"), base::UserError);
  ModelEdits bad;
  bad.joints = {{"right_knee", base::Json{{"lock", 2.0}}}};  // outside [-3.14, 0]
  EXPECT_THROW(edit_model(model, bad), base::UserError);
  bad.joints = {{"right_shoulder", base::Json{{"swing", -1}}}};
  try {
    edit_model(model, bad);
    FAIL() << "a negative swing cone was accepted";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("joints[0].swing: -1 is not an angle in"), std::string::npos) << e.what();
  }
  bad.joints = {{"wing", base::Json{{"lock", 0.0}}}};
  EXPECT_THROW(edit_model(model, bad), base::UserError);
}

// The thesis's body variations: every mass and inertia × s, the geometry and joints as they were.
TEST(WorldJoints, MassScaleMultipliesEveryMassAndInertia) {
  for (const char* name : {"athlete", "humanoid34", "humanoid21"}) {
    const ModelPtr model = load_shipped_model(name);
    ModelEdits edits;
    edits.mass_scale = 1.25;
    const ModelPtr heavier = edit_model(model, edits);
    EXPECT_NEAR(heavier->total_mass(), 1.25 * model->total_mass(), 1e-9 * model->total_mass()) << name;
    ASSERT_EQ(heavier->links().size(), model->links().size());
    for (std::size_t i = 0; i < model->links().size(); ++i) {
      const Link &a = model->links()[i], &b = heavier->links()[i];
      EXPECT_NEAR(b.mass, 1.25 * a.mass, 1e-9) << name << " link " << a.name;
      EXPECT_LT((b.inertia - 1.25 * a.inertia).norm(), 1e-9) << name << " link " << a.name;
      EXPECT_LT((b.com - a.com).norm(), 1e-12) << name << " link " << a.name;
    }
  }
  ModelEdits bad;
  bad.mass_scale = 0.0;
  EXPECT_THROW(edit_model(load_shipped_model("athlete"), bad), base::UserError);
}

// A free-floating body and an arm on one hinge with passive damping d and stiffness k (MuJoCo's
// joint damping and stiffness), no gravity, released at rest at 0.5 rad.
ModelPtr sprung_arm(double damping, double stiffness) {
  base::Json model = base::Json::parse(R"({
    "name": "arm", "standing_root_height": 1.0,
    "bodies": [
      {"name": "base", "mass": 10, "geoms": [{"type": "box", "half_extents": [0.2, 0.2, 0.05]}]},
      {"name": "arm", "parent": "base", "pos": [0, 0, -0.1], "mass": 1,
       "geoms": [{"type": "capsule", "fromto": [0, 0, 0, 0, 0, -0.5], "radius": 0.03}],
       "joints": [{"name": "hinge", "type": "revolute", "axis": [0, 1, 0], "torque_limit": 10}]}]})");
  model["bodies"][1]["joints"][0]["damping"] = damping;
  model["bodies"][1]["joints"][0]["stiffness"] = stiffness;
  return CharacterModel::from_json(model, "sprung arm");
}

struct Swing {
  double q_end = 0.0;
  std::vector<double> energy;  // kinetic + ½ k q², per control step
  int zero_crossings = 0;
};

Swing swing(const ModelPtr& model, bool passive, double seconds) {
  WorldConfig config;
  config.gravity.setZero();
  config.passive_joints = passive;
  World world(model, config);
  Eigen::VectorXd q = model->standing_pose();
  q(2) = 1.0;
  q(7) = 0.5;
  world.reset(q, Eigen::VectorXd::Zero(model->nv()));
  const double k = model->stiffness()(6);
  Swing out;
  for (int step = 0; step < static_cast<int>(seconds * config.control_hz); ++step) {
    const double before = world.data().q(7);
    EXPECT_TRUE(world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
    const double after = world.data().q(7);
    if ((before > 0) != (after > 0)) ++out.zero_crossings;
    out.energy.push_back(world.kinetic_energy() + 0.5 * k * after * after);
  }
  out.q_end = world.data().q(7);
  return out;
}

TEST(WorldJoints, PassiveStiffnessSwingsTheJointAndDampingStopsIt) {
  // Off (the default), nothing acts on the resting arm.
  EXPECT_EQ(swing(sprung_arm(0.5, 4.0), false, 1.0).q_end, 0.5);
  // A spring alone: the arm swings through q = 0 (about 2 times per period), and the energy stays
  // within 2 % of the ½ k q0² it was released with.
  const Swing spring = swing(sprung_arm(0.0, 4.0), true, 3.0);
  EXPECT_GE(spring.zero_crossings, 4);
  for (double e : spring.energy) EXPECT_NEAR(e, 0.5 * 4.0 * 0.25, 0.02 * 0.5);
  // With damping the energy only falls, and after 3 s less than 1 % of it is left.
  const Swing damped = swing(sprung_arm(0.5, 4.0), true, 3.0);
  for (std::size_t i = 1; i < damped.energy.size(); ++i)
    EXPECT_LE(damped.energy[i], damped.energy[i - 1] + 1e-12) << "control step " << i;
  EXPECT_LT(damped.energy.back(), 0.01 * 0.5);
  EXPECT_LT(std::abs(damped.q_end), 0.05);
  std::printf("spring: %d zero crossings in 3 s, energy %.4f..%.4f J (released with 0.5 J); damped: %.2e J left, q %.4f rad\n",
              spring.zero_crossings, *std::min_element(spring.energy.begin(), spring.energy.end()),
              *std::max_element(spring.energy.begin(), spring.energy.end()), damped.energy.back(), damped.q_end);
}

// A sphere of mass m and radius r on a hinge 0.4 m from its centre, hung from a base heavy enough
// to stand still (1e9 kg), no gravity: the hinge's inertia is I = 2/5 m r² + m d², and a torque step
// τ from rest gives q̇(t) = τ t / (I + armature) (MuJoCo adds armature to M's diagonal).
ModelPtr hinged_ball(double armature) {
  base::Json model = base::Json::parse(R"({
    "name": "ball", "standing_root_height": 2.0,
    "bodies": [
      {"name": "base", "mass": 1e9, "geoms": [{"type": "box", "half_extents": [0.2, 0.2, 0.05]}]},
      {"name": "ball", "parent": "base", "pos": [0, 0, -0.1], "mass": 2,
       "geoms": [{"type": "sphere", "pos": [0, 0, -0.4], "radius": 0.1}],
       "joints": [{"name": "hinge", "type": "revolute", "axis": [0, 1, 0], "torque_limit": 100}]}]})");
  model["bodies"][1]["joints"][0]["armature"] = armature;
  return CharacterModel::from_json(model, "hinged ball");
}

double hinge_rate_after(const ModelPtr& model, double torque, double seconds) {
  WorldConfig config;
  config.gravity.setZero();
  World world(model, config);
  Eigen::VectorXd q = model->standing_pose();
  q(2) = 2.0;
  world.reset(q, Eigen::VectorXd::Zero(model->nv()));
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model->nv());
  tau(6) = torque;
  for (int step = 0; step < static_cast<int>(std::lround(seconds * config.control_hz)); ++step)
    EXPECT_TRUE(world.control_step(Control::torque, tau).ok);
  return world.data().qd(6);
}

TEST(WorldJoints, ArmatureAddsToTheHingesInertiaAsTheClosedFormSays) {
  const double m = 2.0, r = 0.1, d = 0.4, inertia = 0.4 * m * r * r + m * d * d, torque = 3.0, t = 0.25;
  for (const double armature : {0.0, 0.01, 0.5}) {
    const double rate = hinge_rate_after(hinged_ball(armature), torque, t);
    EXPECT_NEAR(rate, torque * t / (inertia + armature), 1e-6 * torque * t / inertia) << "armature " << armature;
  }
  // humanoid21_seed carries the seed repository's armature 0.01 on every hinge; humanoid21 none.
  const ModelPtr seed = load_shipped_model("humanoid21_seed"), plain = load_shipped_model("humanoid21");
  EXPECT_TRUE(seed->has_armature());
  EXPECT_FALSE(plain->has_armature());
  EXPECT_EQ(seed->armature().tail(seed->nv() - 6), Eigen::VectorXd::Constant(seed->nv() - 6, 0.01));
  EXPECT_EQ(seed->armature().head<6>(), Eigen::VectorXd::Zero(6));
}

TEST(WorldJoints, ArmatureReachesStablePdBothWays) {
  // SPD's dense solve factors M (CRBA, armature included); MABA adds it to each joint's D: one
  // control step from the same state agrees.
  const ModelPtr model = load_shipped_model("humanoid21_seed");
  base::Rng rng(5);
  const Eigen::VectorXd target = random_pose(*model, rng, 0.0, 0.6);
  std::vector<Eigen::VectorXd> rates;
  for (const Control mode : {Control::spd_dense, Control::spd_maba}) {
    World world(model, WorldConfig{});
    Eigen::VectorXd q = model->standing_pose();
    q(2) += 0.5;  // in the air: no contacts
    world.reset(q, Eigen::VectorXd::Zero(model->nv()));
    EXPECT_TRUE(world.control_step(mode, target).ok);
    rates.push_back(world.data().qd);
  }
  EXPECT_LT((rates[0] - rates[1]).cwiseAbs().maxCoeff(), 1e-8);
}

// A hand (a sphere on a hinge about x through its centre) on an arm with a ball joint 0.35 m to its
// side, touching the face x = 0.1 of a heavy torso box, no gravity: −20 N·m about z presses it on
// the face (≈ 57 N), 3 N·m about x pushes it along the face (≈ 8.6 N, downwards). With μ = 1
// friction holds it (up to ≈ 57 N); with the model's self_contact_friction 0 (the seed's condim 1)
// it slides.
ModelPtr hand_on_torso(bool frictionless) {
  base::Json model = base::Json::parse(R"({
    "name": "hand", "standing_root_height": 2.0,
    "bodies": [
      {"name": "torso", "mass": 1e6, "geoms": [{"type": "box", "half_extents": [0.1, 0.2, 0.3]}]},
      {"name": "arm", "parent": "torso", "pos": [0.149, 0.35, 0], "mass": 0.2,
       "geoms": [{"type": "sphere", "radius": 0.02}],
       "joints": [{"name": "shoulder", "type": "spherical", "torque_limit": 100}]},
      {"name": "hand", "parent": "arm", "pos": [0, -0.35, 0], "mass": 1,
       "geoms": [{"type": "sphere", "radius": 0.05}],
       "joints": [{"name": "wrist", "type": "revolute", "axis": [1, 0, 0], "torque_limit": 100}]}]})");
  if (frictionless) model["self_contact_friction"] = 0.0;
  return CharacterModel::from_json(model, "hand on torso");
}

struct Slide {
  double hand_z_m = 0.0;
  bool touched = true;  // at every control step
};

Slide slide(const ModelPtr& model, double seconds) {
  WorldConfig config;
  config.gravity.setZero();
  World world(model, config);
  Eigen::VectorXd q = model->standing_pose();
  q(2) = 2.0;
  world.reset(q, Eigen::VectorXd::Zero(model->nv()));
  const int hand = model->find_body("hand"), torso = model->find_body("torso");
  const int shoulder = model->link("shoulder").v_index;
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model->nv());
  tau(shoulder) = 3.0;        // about x: along the face
  tau(shoulder + 2) = -20.0;  // about z: into the face
  Slide out;
  const double z0 = world.body_centroid(hand).z();
  for (int step = 0; step < static_cast<int>(std::lround(seconds * config.control_hz)); ++step) {
    EXPECT_TRUE(world.control_step(Control::torque, tau).ok);
    out.touched = out.touched && world.observe().touches(hand, Partner::body, torso);
  }
  out.hand_z_m = world.body_centroid(hand).z() - z0;
  return out;
}

TEST(WorldContacts, FrictionlessSelfContactLetsAHandSlideAlongTheTorso) {
  const Slide held = slide(hand_on_torso(false), 0.2), slid = slide(hand_on_torso(true), 0.2);
  EXPECT_TRUE(held.touched);
  EXPECT_TRUE(slid.touched);
  EXPECT_LT(std::abs(held.hand_z_m), 5e-3);  // the friction pyramid's creep (measured 1.2 mm)
  EXPECT_LT(slid.hand_z_m, -0.05);           // free: about ½ (F/m) t² ≈ 0.17 m
  std::printf("hand moved %.2e m along the torso with μ = 1, %.4f m frictionless\n", held.hand_z_m, slid.hand_z_m);
  // Ground contacts keep their friction: humanoid21_seed is frictionless between its own bodies only.
  EXPECT_EQ(load_shipped_model("humanoid21_seed")->self_contact_friction(), 0.0);
  EXPECT_FALSE(load_shipped_model("humanoid21")->self_contact_friction().has_value());
}

// A snapshot taken mid-rollout on humanoid34 with ground and box contacts, restored after other
// episodes (other props, friction, forces) and into a fresh World, replays 2 s bitwise.
TEST(WorldSnapshot, RestoredRolloutIsBitwiseTheOriginal) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  config.terrain.boxes = {box("mat", Eigen::Vector3d(0.6, 0, 0.1), Eigen::Vector3d(0.5, 1.0, 0.1))};
  World world(model, config);
  base::Rng rng(21);
  ASSERT_TRUE(spd_drop(world, rng, 1.0).ok);
  world.set_external_force(model->find_body("chest"), Eigen::Vector3d(5, 0, 0));
  const WorldSnapshot snap = world.snapshot();
  std::vector<Eigen::VectorXd> actions;
  for (int k = 0; k < 80; ++k) actions.push_back(random_pose(*model, rng, 0.0, 0.8));  // 2 s of SPD targets
  std::vector<Eigen::VectorXd> q, qd;
  bool ground = false, prop = false;
  for (const auto& a : actions) {
    ASSERT_TRUE(world.control_step(Control::spd_maba, a).ok);
    q.push_back(world.data().q), qd.push_back(world.data().qd);
    const Observation o = world.observe();  // detection between steps must not change them
    for (const Contact& c : o.contacts) ground |= c.partner == Partner::ground, prop |= c.partner == Partner::prop;
  }
  EXPECT_TRUE(ground && prop);
  auto replay = [&](World& w, const char* what) {
    w.restore(snap);
    for (std::size_t k = 0; k < actions.size(); ++k) {
      ASSERT_TRUE(w.control_step(Control::spd_maba, actions[k]).ok);
      ASSERT_EQ(w.data().q, q[k]) << what << ", control step " << k;
      ASSERT_EQ(w.data().qd, qd[k]) << what << ", control step " << k;
    }
  };
  // Another episode in between: other props, friction, force, a different fall.
  TerrainConfig other;
  other.boxes = {box("step", Eigen::Vector3d(-0.5, 0, 0.2), Eigen::Vector3d(0.3, 0.3, 0.2))};
  world.set_terrain(other);
  world.set_friction(0.4);
  ASSERT_TRUE(spd_drop(world, rng, 1.0).ok);
  replay(world, "same World");
  EXPECT_EQ(world.terrain().config().boxes[0].name, "mat");
  World fresh(model, WorldConfig{});
  replay(fresh, "fresh World");
  WorldConfig slower;
  slower.sim_hz = 400;
  World other_rate(model, slower);
  EXPECT_THROW(other_rate.restore(snap), base::UserError);
  World other_model(load_shipped_model("humanoid21"), WorldConfig{});
  EXPECT_THROW(other_model.restore(snap), base::UserError);
}

// A World whose model was edited (a locked elbow) restores into another World built with the same edits.
TEST(WorldSnapshot, RestoresAcrossWorldsWithTheSameEdits) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  config.edits.joints = {{"right_elbow", base::Json{{"lock", 0.8}}}};
  World a(model, config), b(model, config);
  base::Rng rng(4);
  ASSERT_TRUE(spd_drop(a, rng, 0.5).ok);
  const WorldSnapshot snap = a.snapshot();
  const Eigen::VectorXd target = random_pose(a.model(), rng, 0.0, 0.8);
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(a.control_step(Control::spd_maba, target).ok);
  b.restore(snap);
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(b.control_step(Control::spd_maba, target).ok);
  EXPECT_EQ(a.data().q, b.data().q);
  EXPECT_EQ(a.data().qd, b.data().qd);
}

}  // namespace
}  // namespace podium::sim
