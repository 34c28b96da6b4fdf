// Stepping, control, stability, starts and observations on real Bullet worlds.
#include "podium/sim/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>
#include <vector>

#include "podium/base/error.h"
#include "podium/sim/starts.h"

namespace podium::sim {
namespace {

// Holds the standing pose for 10 s at Δt = 1/60 s; returns the head heights seen (lowest and
// highest; a blow-up that throws the body up is not standing either).
struct HeadRange {
  double lowest = std::numeric_limits<double>::infinity(), highest = -std::numeric_limits<double>::infinity();
};
HeadRange hold_standing(Control control) {
  const ModelPtr model = load_shipped_model("humanoid21");
  WorldConfig config;
  config.sim_hz = 60.0;
  config.control_hz = 60.0;
  World world(model, config);
  // Model gains (seed App. D: kp = torque limit, kd = kp/10) on the joints, and the thesis's
  // root servo (§2.4.1: kp = 20000, kd = 2000): with light feet, no ankle spring can balance
  // the body at 60 Hz (effective ankle stiffness ≤ I_foot/Δt², see sim/README.md).
  Gains gains = Gains::from_model(*model);
  gains.kp.head<6>().setConstant(20000.0);
  gains.kd.head<6>().setConstant(2000.0);
  world.set_gains(gains);
  HeadRange range;
  for (int k = 0; k <= 600; ++k) {
    if (k > 0 && !world.control_step(control, model->standing_pose()).ok) return {-1e9, 1e9};
    const double head = world.observe().head_height_m;
    range.lowest = std::min(range.lowest, head);
    range.highest = std::max(range.highest, head);
  }
  return range;
}

// "Holding the standing pose": the head stays within ±10% of its standing height for 10 s.
TEST(SpdStability, StablePdHoldsStandingAt60HzWherePlainPdDiverges) {
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, WorldConfig{});
  const double standing = world.observe().head_height_m;
  const HeadRange spd = hold_standing(Control::spd_maba), pd = hold_standing(Control::pd);
  std::printf("standing head %.3f m; head over 10 s at 60 Hz: SPD %.3f to %.3f m, PD %.3g to %.3g m\n", standing, spd.lowest,
              spd.highest, pd.lowest, pd.highest);
  EXPECT_GT(spd.lowest, 0.9 * standing);
  EXPECT_LT(spd.highest, 1.1 * standing);
  EXPECT_TRUE(pd.lowest < 0.9 * standing || pd.highest > 1.1 * standing);
}

// Unassisted balance needs stiff ankles, hence low damping (kd = kp/100) and a high rate.
TEST(SpdStability, StandsUnassistedAt800Hz) {
  const ModelPtr model = load_shipped_model("humanoid21");
  WorldConfig config;
  config.control_hz = 800;
  config.torque_limits = false;
  World world(model, config);
  Gains gains = Gains::from_model(*model);
  gains.kp *= 20.0;
  gains.kd = gains.kp / 100.0;
  world.set_gains(gains);
  const double standing = world.observe().head_height_m;
  double lowest = standing;
  for (int k = 0; k < 8000; ++k) {
    ASSERT_TRUE(world.control_step(Control::spd_maba, model->standing_pose()).ok);
    lowest = std::min(lowest, world.observe().head_height_m);
  }
  EXPECT_GT(lowest, 0.95 * standing);
}

// The PD inside the velocity solve (Control::spd_implicit): humanoid34 on twice DeepMimic's gains
// (kd = kp/10, torque limits on) stands unassisted for 5 s at the curve get-up seed's 60 Hz, where
// SPD computed before the contact solve (spd_maba) falls at 60 and at 600 Hz alike: its ankle
// stiffness is capped near I_foot/Δt² (sim/README.md). With DeepMimic's own gains the ankles
// (2 × 300 N·m/rad against m g h_COM ≈ 560) are too weak for a passive stance in either mode.
TEST(SpdStability, ThePdInsideTheSolveStandsUnassistedAt60Hz) {
  const ModelPtr model = load_shipped_model("humanoid34");
  const auto hold = [&](Control mode, double hz) {
    WorldConfig config;
    config.sim_hz = hz;
    config.control_hz = 30;
    World world(model, config);
    Gains gains = Gains::from_model(*model);
    gains.kp *= 2.0, gains.kd *= 2.0;
    world.set_gains(gains);
    HeadRange range{world.observe().head_height_m, world.observe().head_height_m};
    for (int k = 0; k < 150; ++k) {
      if (!world.control_step(mode, model->standing_pose()).ok) return HeadRange{-1.0, -1.0};
      range.lowest = std::min(range.lowest, world.observe().head_height_m);
      range.highest = std::max(range.highest, world.observe().head_height_m);
    }
    return range;
  };
  const double standing = World(model, WorldConfig{}).observe().head_height_m;
  for (const double hz : {60.0, 600.0}) {
    const HeadRange inside = hold(Control::spd_implicit, hz), outside = hold(Control::spd_maba, hz);
    std::printf("%3.0f Hz, 5 s: head %.3f to %.3f m with the PD inside the solve, %.3f to %.3f m outside (standing %.3f)\n", hz,
                inside.lowest, inside.highest, outside.lowest, outside.highest, standing);
    EXPECT_GT(inside.lowest, 0.99 * standing) << hz;
    EXPECT_LT(inside.highest, 1.01 * standing) << hz;
    EXPECT_LT(outside.lowest, 0.5 * standing) << hz;  // fallen
  }
}

// The law spd_implicit applies: τ = −Kp(q + Δt q̇⁺ − q̄) − Kd q̇⁺ with q̇⁺ the step's new velocity (what
// data().tau reports), on a hinge not at its torque limit, in contact with the ground; and no
// reported torque passes a limit.
TEST(SpdStability, ThePdInsideTheSolveAppliesTheImplicitLaw) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  config.sim_hz = 60;
  config.control_hz = 60;
  World world(model, config);
  Eigen::VectorXd target = model->standing_pose();
  const Link& knee = model->link("right_knee");
  target(knee.q_index) -= 0.3;
  const Gains gains = Gains::from_model(*model);
  for (int k = 0; k < 30; ++k) {
    const Eigen::VectorXd q = world.data().q;
    ASSERT_TRUE(world.control_step(Control::spd_implicit, target).ok);
    const double qd = world.data().qd(knee.v_index), tau = world.data().tau(knee.v_index);
    const double limit = model->torque_limits()(knee.v_index);
    if (std::abs(tau) < limit - 1e-9) {
      const double dt = 1.0 / config.sim_hz;
      const double law =
          -gains.kp(knee.v_index) * (q(knee.q_index) + dt * qd - target(knee.q_index)) - gains.kd(knee.v_index) * qd;
      EXPECT_NEAR(tau, law, 1e-6 * std::max(1.0, std::abs(law))) << k;
    }
    for (int i = 6; i < model->nv(); ++i) EXPECT_LE(std::abs(world.data().tau(i)), model->torque_limits()(i) + 1e-9) << k;
  }
}

TEST(SpdStability, DenseAndMabaGiveTheSameTrajectory) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  config.sim_hz = 600;
  config.control_hz = 30;
  config.self_collision = false;
  World a(model, config), b(model, config);
  base::Rng rng(3);
  // In the air, no self-collision: contacts would amplify round-off differences chaotically.
  const Eigen::VectorXd q0 = random_pose(*model, rng, 100.0, 0.3);
  a.set_state(q0, Eigen::VectorXd::Zero(model->nv()));
  b.set_state(q0, Eigen::VectorXd::Zero(model->nv()));
  const Eigen::VectorXd target = random_pose(*model, rng, 1.0, 0.5);
  for (int k = 0; k < 15; ++k) {
    ASSERT_TRUE(a.control_step(Control::spd_dense, target).ok);
    ASSERT_TRUE(b.control_step(Control::spd_maba, target).ok);
  }
  EXPECT_LE((a.data().q - b.data().q).lpNorm<Eigen::Infinity>(), 1e-6);
}

TEST(RagdollStart, EndsLyingDownFor100Seeds) {
  // Two rollout threads share one model, each with its own World (the intended threading).
  const ModelPtr model = load_shipped_model("humanoid21");
  struct Result {
    double head = 0, energy = 0;
    bool ok = true, finite = true;
  };
  std::vector<Result> results(100);
  auto run = [&](int first) {
    World world(model, WorldConfig{});  // get-up seed: 800 Hz / 40 Hz, μ = 1
    for (int seed = first; seed < 100; seed += 2) {
      base::Rng rng(static_cast<std::uint64_t>(seed));
      Result& r = results[seed];
      r.ok = ragdoll_start(world, rng).ok;
      r.head = world.observe().head_height_m;
      r.energy = world.kinetic_energy();
      r.finite = world.data().q.allFinite() && world.data().qd.allFinite();
    }
  };
  std::thread other(run, 1);
  run(0);
  other.join();
  double worst_head = 0, worst_energy = 0;
  for (int seed = 0; seed < 100; ++seed) {
    const Result& r = results[seed];
    EXPECT_TRUE(r.ok && r.finite) << "seed " << seed;
    EXPECT_LT(r.head, 0.5) << "seed " << seed;
    // Bounded energy: far below the potential energy of the 1.5 m drop (m g h ≈ 600 J).
    EXPECT_LT(r.energy, model->total_mass() * 9.81 * 1.5) << "seed " << seed;
    worst_head = std::max(worst_head, r.head);
    worst_energy = std::max(worst_energy, r.energy);
  }
  std::printf("100 ragdoll starts: highest final head %.3f m, largest final kinetic energy %.2f J\n", worst_head, worst_energy);
}

// humanoid34's light feet on spherical ankles: without swing/twist limits the undamped random
// torques spun them up in the air until the explicit step diverged (5 of 5 seeds).
TEST(RagdollStart, Humanoid34StaysFiniteFor30Seeds) {
  const ModelPtr model = load_shipped_model("humanoid34");
  World world(model, WorldConfig{});
  int finite = 0;
  double worst_head = 0, worst_energy = 0;
  for (std::uint64_t seed = 0; seed < 30; ++seed) {
    base::Rng rng(seed);
    const bool ok = ragdoll_start(world, rng).ok && world.data().q.allFinite() && world.data().qd.allFinite();
    EXPECT_TRUE(ok) << "seed " << seed;
    if (!ok) continue;
    ++finite;
    const double head = world.observe().head_height_m, energy = world.kinetic_energy();
    EXPECT_LT(head, 0.5) << "seed " << seed;
    EXPECT_LT(energy, model->total_mass() * 9.81 * 1.5) << "seed " << seed;
    worst_head = std::max(worst_head, head), worst_energy = std::max(worst_energy, energy);
  }
  std::printf("humanoid34: %d of 30 ragdoll starts finite; highest final head %.3f m, largest final kinetic energy %.2f J\n",
              finite, worst_head, worst_energy);
}

// A fall asked to land supine or prone at a place does, on humanoid34 with its limits.
TEST(RagdollStart, LandsSupineOrProneWhereAsked) {
  const ModelPtr model = load_shipped_model("humanoid34");
  World world(model, WorldConfig{});
  for (const auto lying : {RagdollStart::Lying::supine, RagdollStart::Lying::prone}) {
    RagdollStart fall;
    fall.lying = lying;
    fall.x_m = 2.0, fall.y_m = -1.0;
    fall.random_yaw = true;
    int right = 0;
    for (std::uint64_t seed = 0; seed < 5; ++seed) {
      base::Rng rng(seed);
      ASSERT_TRUE(ragdoll_start(world, rng, fall).ok) << "seed " << seed;
      const Eigen::Vector3d front = world.data().links[model->bodies()[model->torso_body()].link].R.col(0);
      right += (front.z() > 0) == (lying == RagdollStart::Lying::supine);
      EXPECT_NEAR(world.data().q(0), 2.0, 1.5) << "seed " << seed;
      EXPECT_NEAR(world.data().q(1), -1.0, 1.5) << "seed " << seed;
    }
    std::printf("humanoid34 %s: %d of 5 falls land that way\n", lying == RagdollStart::Lying::supine ? "supine" : "prone", right);
    EXPECT_GE(right, 4);
  }
}

// A tumbling character without gravity, contacts or torques for 1 s at `hz`: the drift of its
// centre-of-mass velocity and of its kinetic energy, relative to their initial values.
struct Drift {
  double velocity = 0, energy = 0;
};
Drift tumble(double hz) {
  const ModelPtr model = load_shipped_model("humanoid21");
  WorldConfig config;
  config.sim_hz = hz;
  config.control_hz = hz;
  config.gravity.setZero();
  config.self_collision = false;
  config.joint_limits = false;
  World world(model, config);
  base::Rng rng(7);
  Eigen::VectorXd qd(model->nv());
  for (int i = 0; i < model->nv(); ++i) qd(i) = rng.normal(0.0, 2.0);
  world.reset(random_pose(*model, rng, 10.0), qd);
  Eigen::Vector3d com, vel0, vel;
  CharacterData data = world.data();
  center_of_mass(*model, data, com, vel0);
  const double energy0 = world.kinetic_energy();
  for (int k = 0; k < static_cast<int>(hz); ++k)
    EXPECT_TRUE(world.sim_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
  data = world.data();
  center_of_mass(*model, data, com, vel);
  return {(vel - vel0).norm() / vel0.norm(), std::abs(world.kinetic_energy() - energy0) / energy0};
}

// Momentum and energy drift of the step's semi-implicit Euler shrink with Δt (a root update that
// dropped ω × v and ω × (ω × c) gained hundreds of joules per ragdoll drop at any Δt). Light hinge
// links spinning at several rad/s drift visibly at 800 Hz, hence the comparison with 8 kHz.
TEST(World, FreeTumblingConservesMomentumAndEnergyAsDtShrinks) {
  const Drift coarse = tumble(800.0), fine = tumble(8000.0);
  std::printf("1 s tumbling, relative drift at 800 Hz / 8 kHz: COM velocity %.2e / %.2e, kinetic energy %.2e / %.2e\n",
              coarse.velocity, fine.velocity, coarse.energy, fine.energy);
  EXPECT_LT(fine.velocity, 0.01);
  EXPECT_LT(fine.energy, 0.01);
  EXPECT_LT(5 * fine.velocity, coarse.velocity);
  EXPECT_LT(5 * fine.energy, coarse.energy);
}

TEST(World, RolloutDependsOnlyOnItsSeedNotOnWorldHistory) {
  const ModelPtr model = load_shipped_model("humanoid21");
  World fresh(model, WorldConfig{}), used(model, WorldConfig{});
  base::Rng warmup(3);
  ragdoll_start(used, warmup);
  base::Rng a(5), b(5);
  ragdoll_start(fresh, a);
  ragdoll_start(used, b);
  EXPECT_EQ(fresh.data().q, used.data().q);
  EXPECT_EQ(fresh.data().qd, used.data().qd);
}

TEST(World, SetStateWorldTakesWorldFrameRootVelocities) {
  const ModelPtr model = load_shipped_model("humanoid34");
  World world(model, WorldConfig{});
  Eigen::VectorXd q = model->standing_pose();
  const Eigen::Quaterniond yaw(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  q.segment<4>(3) << yaw.w(), yaw.x(), yaw.y(), yaw.z();
  world.set_state_world(q, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(2, 0, 0), Eigen::VectorXd::Zero(model->nv() - 6));
  // Root frame is yawed 90°: world +x is root −y.
  EXPECT_NEAR(world.data().qd(4), -2.0, 1e-12);
  EXPECT_NEAR(world.data().qd(2), 1.0, 1e-12);
  EXPECT_NEAR(world.observe().com_vel.x(), 2.0, 0.5);  // COM off the root axis adds ω × r
}

TEST(World, DivergenceIsReportedWithDofAndStep) {
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, WorldConfig{});
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
  qd(10) = std::numeric_limits<double>::quiet_NaN();
  world.set_state(model->standing_pose(), qd);
  const StepReport r = world.control_step(Control::spd_maba, model->standing_pose());
  EXPECT_FALSE(r.ok);
  EXPECT_GE(r.bad_dof, 0);
  EXPECT_EQ(r.bad_step, 1);
  EXPECT_FALSE(world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);  // stays failed until reset
  world.reset(model->standing_pose(), Eigen::VectorXd::Zero(model->nv()));
  EXPECT_TRUE(world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
}

TEST(World, ASpeedNoBodyReachesIsReportedAsDivergence) {
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, WorldConfig{});
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
  qd(3) = 5e3;  // the root flies at 5 km/s: finite, but no body moves so
  world.set_state(model->standing_pose(), qd);
  const StepReport r = world.sim_step(Control::torque, Eigen::VectorXd::Zero(model->nv()));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.bad_dof, 3);
  EXPECT_EQ(r.bad_step, 1);
  qd(3) = 50.0;  // fast, but a body can move so
  world.reset(model->standing_pose(), qd);
  EXPECT_TRUE(world.sim_step(Control::torque, Eigen::VectorXd::Zero(model->nv())).ok);
}

TEST(World, StrengthMultiplierScalesTorqueLimits) {
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, WorldConfig{});
  Eigen::VectorXd tau = Eigen::VectorXd::Constant(model->nv(), 1e4);
  world.set_strength(0.5);
  world.sim_step(Control::torque, tau);
  EXPECT_NEAR(world.data().tau(6 + 5), 0.5 * 120.0, 1e-12);  // hip_y_right: 120 N·m in Table 2
  EXPECT_EQ(world.data().tau.head<6>().norm(), 0.0);
}

TEST(World, JointLimitsHold) {
  const ModelPtr model = load_shipped_model("humanoid21");
  World world(model, WorldConfig{});
  const int knee = model->find_link("knee_right");
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model->nv());
  tau(model->links()[knee].v_index) = 80.0;  // push the knee past its 0.03 rad upper limit
  for (int k = 0; k < 20; ++k) world.control_step(Control::torque, tau);
  EXPECT_LT(world.data().q(model->links()[knee].q_index), 0.03 + 0.02);
}

TEST(World, RejectsControlRateThatDoesNotDivide) {
  WorldConfig config;
  config.sim_hz = 800;
  config.control_hz = 30;
  const ModelPtr model = load_shipped_model("humanoid21");
  EXPECT_THROW({ World world(model, config); }, base::UserError);
}

TEST(World, SetStateRoundTripsAndObservesStanding) {
  const ModelPtr model = load_shipped_model("humanoid34");
  World world(model, WorldConfig{});
  base::Rng rng(9);
  const Eigen::VectorXd q = random_pose(*model, rng, 2.0, 0.5);
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
  for (int i = 0; i < model->nv(); ++i) qd(i) = rng.normal();
  world.set_state(q, qd);
  EXPECT_LE((world.data().qd - qd).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_LE((world.data().q.head<3>() - q.head<3>()).norm(), 1e-12);
  standing_start(world);
  const Observation o = world.observe();
  EXPECT_NEAR(o.head_height_m, 1.58, 0.03);  // head centre; top of head at ~1.70 m
  EXPECT_NEAR(o.torso_up.z(), 1.0, 1e-9);
  EXPECT_EQ(o.end_effectors.size(), 4u);
  world.control_step(Control::spd_maba, model->standing_pose());
  const Observation after = world.observe();
  EXPECT_TRUE(after.body_contacts[model->find_body("right_foot")]);
  EXPECT_FALSE(after.body_contacts[model->find_body("head")]);
}

}  // namespace
}  // namespace podium::sim
