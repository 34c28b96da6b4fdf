// The shipped athlete (sim/models/athlete.json, made by make_athlete.py): the thesis's simulated
// athlete of Table 3.2 (60 kg, 1.70 m, hips 0.95 m, knees 0.46 m) with the jumper's leg torque
// limits (§3.6.2), holding its standing pose by stable PD in a real Bullet world.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "podium/sim/dynamics.h"
#include "podium/sim/world.h"
#include "shared_data.h"

namespace podium::sim {
namespace {

// Highest world z of any geom (the top of the head when standing); needs forward_kinematics.
double highest_geom_point(const CharacterModel& model, const CharacterData& data) {
  double top = -1e9;
  for (std::size_t i = 0; i < model.links().size(); ++i) {
    const LinkData& d = data.links[i];
    for (const Geom& g : model.links()[i].geoms) {
      const Eigen::Vector3d c = d.p + d.R * g.pos;
      const Eigen::Matrix3d R = d.R * g.rot.toRotationMatrix();
      switch (g.type) {
        case ShapeType::sphere:
          top = std::max(top, c.z() + g.radius);
          break;
        case ShapeType::capsule:
          top = std::max(top, c.z() + g.half_length * std::abs(R(2, 2)) + g.radius);
          break;
        case ShapeType::box:
          top = std::max(top, c.z() + R.row(2).cwiseAbs().dot(g.half_extents));
          break;
      }
    }
  }
  return top;
}

struct Standing {
  double top = 0, sole = 0;
  double hip[2] = {0, 0}, knee[2] = {0, 0};  // right, left: joint centres above the ground, m
};

Standing standing_figures(const CharacterModel& m) {
  CharacterData data(m);
  data.q = m.standing_pose();
  forward_kinematics(m, data);
  Standing s;
  s.top = highest_geom_point(m, data);
  s.sole = lowest_geom_point(m, data);
  const char* side[2] = {"right", "left"};
  for (int k = 0; k < 2; ++k) {
    s.hip[k] = data.links[m.find_link(std::string(side[k]) + "_hip")].p.z();
    s.knee[k] = data.links[m.find_link(std::string(side[k]) + "_knee")].p.z();
  }
  return s;
}

Eigen::VectorXd joint_limits(const CharacterModel& m, const std::string& joint) {
  const Link& l = m.link(joint);
  return m.torque_limits().segment(l.v_index, l.nv);
}

TEST(Athlete, HasTable3_2MassHeightAndJointHeights) {
  const ModelPtr m = load_shipped_model("athlete");
  const Standing s = standing_figures(*m);
  std::printf("athlete: %.3f kg, head top %.4f m, soles %.4f m, hips %.4f/%.4f m, knees %.4f/%.4f m, nv %d\n", m->total_mass(),
              s.top, s.sole, s.hip[0], s.hip[1], s.knee[0], s.knee[1], m->nv());
  EXPECT_EQ(m->nv(), 34);      // §3.6.2: 34 DoFs in total,
  EXPECT_EQ(m->nv() - 6, 28);  // 28 internal
  EXPECT_NEAR(m->total_mass(), 60.0, 0.5);
  EXPECT_NEAR(s.sole, 0.0, 1e-3);  // standing on the ground, not in it or above it
  EXPECT_NEAR(s.top, 1.70, 0.02);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(s.hip[k], 0.95, 0.02);
    EXPECT_NEAR(s.knee[k], 0.46, 0.02);
  }
}

// Per axis about the link's x (forward), y (lateral: flexion), z (twist), N·m.
TEST(Athlete, HasTheJumpersLegTorqueLimitsAndDeepMimicsElsewhere) {
  const ModelPtr m = load_shipped_model("athlete");
  for (const char* side : {"right", "left"}) {
    const std::string s(side);
    EXPECT_EQ(joint_limits(*m, s + "_hip"), Eigen::Vector3d(500, 500, 50)) << s;
    EXPECT_EQ(joint_limits(*m, s + "_knee"), Eigen::VectorXd::Constant(1, 400)) << s;
    EXPECT_EQ(joint_limits(*m, s + "_ankle"), Eigen::Vector3d(100, 300, 50)) << s;
    EXPECT_EQ(joint_limits(*m, s + "_shoulder"), Eigen::Vector3d::Constant(100)) << s;
    EXPECT_EQ(joint_limits(*m, s + "_elbow"), Eigen::VectorXd::Constant(1, 60)) << s;
  }
  EXPECT_EQ(joint_limits(*m, "chest"), Eigen::Vector3d::Constant(200));
  EXPECT_EQ(joint_limits(*m, "neck"), Eigen::Vector3d::Constant(50));
}

// The leg limits are the thesis's own character file's (read there when present).
TEST(Athlete, LegTorqueLimitsEqualTheJumperFiles) {
  const std::filesystem::path file = podium::testing::shared_data("jump/data/characters/humanoid3d_jumper60kg.txt");
  if (file.empty()) GTEST_SKIP() << "PODIUM_SHARED_DIR/data/jump is absent: no jumper file to compare with";
  const ModelPtr athlete = load_shipped_model("athlete"), jumper = load_deepmimic(file);
  for (const char* joint : {"right_hip", "left_hip", "right_knee", "left_knee", "right_ankle", "left_ankle"})
    EXPECT_EQ(joint_limits(*athlete, joint), joint_limits(*jumper, joint)) << joint;
}

// Holds the standing pose by stable PD (MABA) at the thesis's 600 Hz simulation and its top 30 Hz
// control rate (§3.6.2: f_control ≤ 30 Hz), torque limits on, for 2 s; returns the head heights
// seen (lowest, highest) and the last observation.
struct Held {
  double start = 0, lowest = 1e9, highest = -1e9;
  Observation end;
};
Held hold_standing(const ModelPtr& m, const Gains& gains) {
  WorldConfig config;
  config.sim_hz = 600.0;
  config.control_hz = 30.0;
  World world(m, config);
  world.set_gains(gains);
  world.reset(m->standing_pose(), Eigen::VectorXd::Zero(m->nv()));
  Held h;
  h.start = h.lowest = h.highest = world.observe().head_height_m;
  for (int k = 0; k < 60; ++k) {
    if (!world.control_step(Control::spd_maba, m->standing_pose()).ok) return {h.start, -1e9, 1e9, {}};
    h.end = world.observe();
    h.lowest = std::min(h.lowest, h.end.head_height_m);
    h.highest = std::max(h.highest, h.end.head_height_m);
  }
  return h;
}

// Unassisted: stiff, lightly damped gains (5 × the model's kp, kd = kp/100). The model's own
// (DeepMimic's, kd = kp/10) cannot balance anything on its ankles here: SPD computed outside the
// contact solve gives a light foot ≈ kp·I_foot/(I_foot + kd·Δt) of stiffness (sim/README.md),
// ≤ 10·I_foot/Δt ≈ 47 N·m/rad per ankle at 600 Hz, where standing needs 2 k ≥ m g h_COM ≈ 556.
// With these gains the bound is 469 and each ankle has ≈ 380: it stands. (The thesis's policies
// balance actively, offsetting the targets.)
TEST(Athlete, StandsUnassistedFor2sOnStiffStablePd) {
  const ModelPtr m = load_shipped_model("athlete");
  Gains gains = Gains::from_model(*m);
  gains.kp *= 5.0;
  gains.kd = gains.kp / 100.0;
  const Held h = hold_standing(m, gains);
  std::printf("athlete unassisted, 2 s: head %.4f m at start, %.4f to %.4f m; COM at the end (%.4f, %.4f, %.4f) m\n", h.start,
              h.lowest, h.highest, h.end.com.x(), h.end.com.y(), h.end.com.z());
  EXPECT_GT(h.lowest, 0.98 * h.start);
  EXPECT_LT(h.highest, 1.02 * h.start);
  EXPECT_GT(h.end.torso_up.z(), 0.99);       // the torso still upright
  EXPECT_LT(std::abs(h.end.com.x()), 0.04);  // the COM still over the feet (ankles at x = 0, toes at 0.14 m)
}

// With its own gains and the thesis's root servo (§2.4.1, kp 20000, kd 2000, as the 60 Hz
// standing test in world_test.cpp): the servo carries the balance and the weight, the model's PD
// holds the chest, head and arms against gravity, within the torque limits.
TEST(Athlete, ItsOwnPdGainsHoldTheStandingPoseFor2sWithTheRootServo) {
  const ModelPtr m = load_shipped_model("athlete");
  Gains gains = Gains::from_model(*m);
  gains.kp.head<6>().setConstant(20000.0);
  gains.kd.head<6>().setConstant(2000.0);
  const Held h = hold_standing(m, gains);
  std::printf("athlete with root servo, 2 s: head %.4f m at start, %.4f to %.4f m\n", h.start, h.lowest, h.highest);
  EXPECT_GT(h.lowest, 0.98 * h.start);
  EXPECT_LT(h.highest, 1.02 * h.start);
  EXPECT_GT(h.end.torso_up.z(), 0.99);
}

}  // namespace
}  // namespace podium::sim
