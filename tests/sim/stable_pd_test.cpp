// Stable PD: MABA (thesis §2.3) against the dense factorisation (eq. 2.7) and the equations of motion.
#include <gtest/gtest.h>

#include <cstdio>

#include "podium/sim/dynamics.h"
#include "test_util.h"

namespace podium::sim {
namespace {

using testing::random_state;
using testing::relative_error;

Eigen::VectorXd random_target(const CharacterModel& model, base::Rng& rng) {
  Eigen::VectorXd q, qd;
  random_state(model, rng, q, qd);
  return q;
}

void expect_maba_matches_dense(const ModelPtr& model, std::uint64_t seed) {
  base::Rng rng(seed);
  CharacterData dense(*model), maba(*model);
  const Gains gains = Gains::from_model(*model);
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    random_state(*model, rng, dense.q, dense.qd);
    maba.q = dense.q;
    maba.qd = dense.qd;
    const Eigen::VectorXd target = random_target(*model, rng);
    const double dt = trial % 2 ? 1.0 / 60.0 : 1.0 / 600.0;
    stable_pd_dense(*model, dense, gains, target, dt);
    stable_pd_maba(*model, maba, gains, target, dt);
    const double err = relative_error(maba.tau, dense.tau);
    EXPECT_LE(err, 1e-8) << model->name() << " trial " << trial;
    EXPECT_LE(relative_error(maba.qdd, dense.qdd), 1e-8) << model->name() << " trial " << trial;
    EXPECT_GT(dense.tau.norm(), 1.0);
    worst = std::max(worst, err);
  }
  std::printf("%s (nv %d): worst relative SPD torque difference MABA vs dense %.2e\n", model->name().c_str(), model->nv(), worst);
}

TEST(StablePdMaba, MatchesDenseOnHumanoid21) { expect_maba_matches_dense(load_shipped_model("humanoid21"), 11); }
TEST(StablePdMaba, MatchesDenseOnHumanoid34) { expect_maba_matches_dense(load_shipped_model("humanoid34"), 12); }
TEST(StablePdMaba, MatchesDenseOn36DofChain) { expect_maba_matches_dense(make_chain(11), 13); }
TEST(StablePdMaba, MatchesDenseOn72DofChain) { expect_maba_matches_dense(make_chain(23), 14); }
TEST(StablePdMaba, MatchesDenseOn195DofChain) {
  const ModelPtr chain = make_chain(64);
  ASSERT_EQ(chain->nv(), 195);
  expect_maba_matches_dense(chain, 15);
}
TEST(StablePdMaba, MatchesDenseOnRevoluteChain) { expect_maba_matches_dense(make_chain(30, JointType::revolute), 16); }

// The root servo with and without its damper: MABA solves an undamped root in world coordinates
// and a damped one through Sᵀ I^A S + K (stable_pd.cpp), so both paths are checked.
void expect_maba_matches_dense_with_root_servo(double root_kd, std::uint64_t seed) {
  const ModelPtr model = load_shipped_model("humanoid21");
  base::Rng rng(seed);
  CharacterData dense(*model), maba(*model);
  Gains gains = Gains::from_model(*model);
  gains.kp.head<6>().setConstant(20000.0);  // thesis §2.4.1 root servo
  gains.kd.head<6>().setConstant(root_kd);
  random_state(*model, rng, dense.q, dense.qd);
  maba.q = dense.q;
  maba.qd = dense.qd;
  const Eigen::VectorXd target = random_target(*model, rng);
  stable_pd_dense(*model, dense, gains, target, 1.0 / 60.0);
  stable_pd_maba(*model, maba, gains, target, 1.0 / 60.0);
  EXPECT_GT(dense.tau.head<6>().norm(), 1.0);
  EXPECT_LE(relative_error(maba.tau, dense.tau), 1e-8);
  EXPECT_LE(relative_error(maba.qdd, dense.qdd), 1e-8);
}

TEST(StablePdMaba, MatchesDenseWithRootServo) { expect_maba_matches_dense_with_root_servo(2000.0, 19); }
TEST(StablePdMaba, MatchesDenseWithUndampedRootSpring) { expect_maba_matches_dense_with_root_servo(0.0, 20); }

TEST(StablePd, TorquesSatisfyEquationsOfMotionAndSpdLawOnHingesAndBalls) {
  const ModelPtr model = load_shipped_model("humanoid34");
  base::Rng rng(17);
  CharacterData data(*model);
  const Gains gains = Gains::from_model(*model);
  random_state(*model, rng, data.q, data.qd);
  const Eigen::VectorXd target = random_target(*model, rng);
  const double dt = 1.0 / 120.0;
  stable_pd_maba(*model, data, gains, target, dt);
  const Eigen::VectorXd tau = data.tau, qdd = data.qdd;
  // The accelerations are those of the free dynamics under the SPD torques: M q̈ + C = τ.
  CharacterData check(*model);
  check.q = data.q;
  check.qd = data.qd;
  forward_dynamics_dense(*model, check, tau);
  EXPECT_LE(relative_error(qdd, check.qdd), 1e-9);
  // Revolute joints obey eq. 2.6 literally.
  for (const Link& l : model->links()) {
    if (l.joint != JointType::revolute) continue;
    const int v = l.v_index;
    const double expected =
        -gains.kp(v) * (data.q(l.q_index) + dt * data.qd(v) - target(l.q_index)) - gains.kd(v) * (data.qd(v) + dt * qdd(v));
    EXPECT_NEAR(tau(v), expected, 1e-9 * std::max(1.0, std::abs(expected)));
  }
  // Ball joints obey it with q − q̄ read as the rotation vector of q̄⁻¹q (shortest arc), here by
  // Eigen's angle-axis conversion.
  int balls = 0;
  for (const Link& l : model->links()) {
    if (l.joint != JointType::spherical) continue;
    ++balls;
    const int v = l.v_index, i = l.q_index;
    const Eigen::Quaterniond cur(data.q(i), data.q(i + 1), data.q(i + 2), data.q(i + 3));
    const Eigen::Quaterniond tgt(target(i), target(i + 1), target(i + 2), target(i + 3));
    Eigen::Quaterniond d = tgt.normalized().conjugate() * cur.normalized();
    if (d.w() < 0) d.coeffs() = -d.coeffs();
    const Eigen::AngleAxisd aa(d);
    const Eigen::Vector3d w = data.qd.segment<3>(v), wd = qdd.segment<3>(v);
    const Eigen::Vector3d expected =
        -gains.kp.segment<3>(v).cwiseProduct(aa.angle() * aa.axis() + dt * w) - gains.kd.segment<3>(v).cwiseProduct(w + dt * wd);
    EXPECT_LE((tau.segment<3>(v) - expected).norm(), 1e-9 * std::max(1.0, expected.norm()));
  }
  EXPECT_EQ(balls, 8);
  EXPECT_EQ(tau.head<6>().norm(), 0.0);  // the root is unactuated
}

TEST(StablePd, ZeroTimeStepIsPlainPd) {
  const ModelPtr model = load_shipped_model("humanoid21");
  base::Rng rng(18);
  CharacterData a(*model), b(*model);
  const Gains gains = Gains::from_model(*model);
  random_state(*model, rng, a.q, a.qd);
  b.q = a.q;
  b.qd = a.qd;
  const Eigen::VectorXd target = random_target(*model, rng);
  stable_pd_maba(*model, a, gains, target, 0.0);
  pd_torques(*model, b, gains, target);
  EXPECT_LE(relative_error(a.tau, b.tau), 1e-12);
}

}  // namespace
}  // namespace podium::sim
