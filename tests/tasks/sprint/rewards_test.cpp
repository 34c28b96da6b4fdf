// The sprint's reward terms and the mirror on hand-made states (sprint seed §2 "Reward", §3.2).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mirror.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/starts.h"
#include "sprint_rewards.h"
#include "track.h"

namespace podium::tasks::sprint {
namespace {

sim::ModelPtr humanoid() { return sim::load_shipped_model("humanoid34"); }

// Sets joint `name`'s quaternion to a rotation of `angle` about `axis`.
void set_joint(const sim::CharacterModel& m, Eigen::VectorXd& q, const char* name, double angle, const Eigen::Vector3d& axis) {
  const Eigen::Quaterniond r(Eigen::AngleAxisd(angle, axis));
  q.segment<4>(m.link(name).q_index) << r.w(), r.x(), r.y(), r.z();
}

void set_yaw(Eigen::VectorXd& q, double yaw) { q.segment<4>(3) << std::cos(yaw / 2), 0, 0, std::sin(yaw / 2); }

TEST(SprintRewards, ForwardTermIsTheRootDisplacementOverTheStep) {
  EXPECT_DOUBLE_EQ(forward_speed(12.0, 12.25, 0.05), 0.25 / 0.05);
  EXPECT_DOUBLE_EQ(forward_speed(3.0, 2.9, 0.1), -0.1 / 0.1);  // backwards is negative
  EXPECT_EQ(forward_speed(4.0, 4.0, 1.0 / 30), 0.0);
}

TEST(SprintRewards, BaseRewardSumsSpeedSurvivalAndLateralTerms) {
  RewardWeights w;
  w.forward = 0.5;
  w.survival = 2.0;
  w.lateral = 3.0;
  const BaseReward running = base_reward(w, 10.0, 10.3, 0.1, 0.0, 1.22, false);
  EXPECT_NEAR(running.forward, 0.5 * 3.0, 1e-12);  // (10.3 − 10) / 0.1 rounds
  EXPECT_EQ(running.survival, 2.0);
  EXPECT_EQ(running.lateral, 0.0);
  EXPECT_NEAR(running.total(), 3.5, 1e-12);
  const BaseReward fallen = base_reward(w, 10.0, 10.3, 0.1, 0.305, 1.22, true);
  EXPECT_EQ(fallen.survival, 0.0);
  EXPECT_DOUBLE_EQ(fallen.lateral, -3.0 * 0.25);  // half-way to the lane's edge
}

TEST(SprintRewards, LateralPenaltyIsZeroAtTheCentreAndGrowsWithTheOffset) {
  const double w = 1.22;
  EXPECT_EQ(lateral_penalty(0.0, w, 2.0), 0.0);
  double last = 0.0;
  for (const double d : {0.05, 0.1, 0.2, 0.4, 0.61}) {
    const double r = lateral_penalty(d, w, 2.0);
    EXPECT_LT(r, last) << d;
    EXPECT_DOUBLE_EQ(lateral_penalty(-d, w, 2.0), r);  // either side
    last = r;
  }
  EXPECT_DOUBLE_EQ(lateral_penalty(0.61, w, 2.0), -2.0);  // −w_d at the lane's edge
}

TEST(SprintRewards, MassPenaltyIsZeroUprightAnywhereOnTheTrackAndNegativeLeaning) {
  const sim::ModelPtr m = humanoid();
  sim::CharacterData data(*m);
  data.q = m->standing_pose();
  const Eigen::Vector3d upright = com_in_heading_frame(*m, data);
  data.q(0) = 37.0;
  data.q(1) = 0.3;
  set_yaw(data.q, 0.7);
  EXPECT_NEAR(mass_penalty(com_in_heading_frame(*m, data), upright, 1.0), 0.0, 1e-12);
  double last = 0.0;
  for (const double lean : {0.2, 0.5, 0.8}) {  // the chest pitched forward
    set_joint(*m, data.q, "chest", lean, Eigen::Vector3d::UnitY());
    const double r = mass_penalty(com_in_heading_frame(*m, data), upright, 1.0);
    EXPECT_LT(r, last) << lean;
    last = r;
  }
}

TEST(SprintRewards, DiagonalSwingScoresHigherThanSameSide) {
  const sim::ModelPtr m = humanoid();
  const SprintBodies b = SprintBodies::of(*m);
  sim::CharacterData data(*m);
  auto swing = [&](double left_hip, double right_hip, double left_shoulder, double right_shoulder) {
    data.q = m->standing_pose();
    set_yaw(data.q, -1.1);  // any heading
    // Forward swing of a hanging limb: a rotation about −y (−z turns towards +x).
    set_joint(*m, data.q, "left_hip", left_hip, -Eigen::Vector3d::UnitY());
    set_joint(*m, data.q, "right_hip", right_hip, -Eigen::Vector3d::UnitY());
    set_joint(*m, data.q, "left_shoulder", left_shoulder, -Eigen::Vector3d::UnitY());
    set_joint(*m, data.q, "right_shoulder", right_shoulder, -Eigen::Vector3d::UnitY());
    sim::forward_kinematics(*m, data);
    return SwingAngles{sagittal_angle(*m, data, b.left_thigh), sagittal_angle(*m, data, b.right_thigh),
                       sagittal_angle(*m, data, b.left_upper_arm), sagittal_angle(*m, data, b.right_upper_arm)};
  };
  const SwingAngles diagonal = swing(0.5, -0.4, -0.45, 0.45), same_side = swing(0.5, -0.4, 0.45, -0.45);
  EXPECT_NEAR(diagonal.left_hip, 0.5, 1e-12);
  EXPECT_NEAR(diagonal.right_hip, -0.4, 1e-12);
  EXPECT_NEAR(diagonal.right_shoulder, 0.45, 1e-12);
  EXPECT_DOUBLE_EQ(diagonal_reward(diagonal, 2.0), 1.0);
  EXPECT_GT(diagonal_reward(diagonal, 2.0), diagonal_reward(same_side, 2.0) + 0.5);
  // The mirror pattern (right leg forward with the left arm) is diagonal too.
  EXPECT_DOUBLE_EQ(diagonal_reward(swing(-0.4, 0.5, 0.45, -0.45), 2.0), 1.0);
  EXPECT_LT(diagonal_reward(swing(-0.4, 0.5, -0.45, 0.45), 2.0), 0.5);
}

// M reflects every body in the plane y = 0: each body of M(q) sits where its twin sits in q,
// mirrored, with the mirrored orientation P R P.
TEST(SprintMirror, ReflectsEveryBodyAndIsItsOwnInverse) {
  const sim::ModelPtr m = humanoid();
  const Mirror mirror(*m);
  base::Rng rng(5);
  const Eigen::Matrix3d P = Eigen::Vector3d(1, -1, 1).asDiagonal();
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q = sim::random_pose(*m, rng, 1.0);
    q(0) = rng.uniform(0, 100);
    q(1) = rng.uniform(-0.5, 0.5);
    const Eigen::VectorXd mq = mirror.apply(q);
    EXPECT_TRUE(mirror.apply(mq) == q);  // bit for bit
    sim::CharacterData a(*m), b(*m);
    a.q = q;
    b.q = mq;
    sim::forward_kinematics(*m, a);
    sim::forward_kinematics(*m, b);
    for (int body = 0; body < static_cast<int>(m->bodies().size()); ++body) {
      std::string twin = m->bodies()[body].name;
      if (twin.rfind("left_", 0) == 0) twin = "right_" + twin.substr(5);
      else if (twin.rfind("right_", 0) == 0) twin = "left_" + twin.substr(6);
      const int t = m->find_body(twin);
      ASSERT_GE(t, 0) << twin;
      const Eigen::Vector3d pa = sim::body_point(*m, a, t, Eigen::Vector3d::Zero()),
                            pb = sim::body_point(*m, b, body, Eigen::Vector3d::Zero());
      EXPECT_LE((pb - P * pa).norm(), 1e-12) << m->bodies()[body].name;
      const Eigen::Matrix3d Ra = a.links[m->bodies()[t].link].R, Rb = b.links[m->bodies()[body].link].R;
      EXPECT_LE((Rb - P * Ra * P).norm(), 1e-12) << m->bodies()[body].name;
    }
    EXPECT_GT(mirror.distance2(q, mq), 0.0);
    EXPECT_EQ(mirror.distance2(q, q), 0.0);
  }
  EXPECT_EQ(mirror.distance2(m->standing_pose(), mirror.apply(m->standing_pose())), 0.0);  // a symmetric pose
}

// An exactly mirrored gait (odd steps the mirror images of even ones, step by step, pose by pose)
// scores r_mirror = 1 from the second step on; one that repeats the same asymmetric step does not.
TEST(SprintMirror, RewardIsOneOnAnExactlyMirroredGait) {
  const sim::ModelPtr m = humanoid();
  const Mirror mirror(*m);
  base::Rng rng(11);
  std::vector<Eigen::VectorXd> step;
  for (int k = 0; k < 6; ++k) step.push_back(sim::random_pose(*m, rng, 1.0, 0.6));
  for (const bool mirrored : {true, false}) {
    StepAlignedPoses history;
    history.reset();
    double x = 0.0;
    for (int s = 0; s < 5; ++s) {
      for (int k = 0; k < static_cast<int>(step.size()); ++k) {
        Eigen::VectorXd q = mirrored && s % 2 == 1 ? mirror.apply(step[k]) : step[k];
        q(0) = (x += 0.2);  // moving on down the track
        if (k == 0) history.touchdown();
        const Eigen::VectorXd* previous = history.aligned_previous();
        ASSERT_EQ(previous == nullptr, s == 0);
        if (previous) {
          const double r = mirror_reward(mirror, q, *previous, 1.0);
          if (mirrored) EXPECT_EQ(r, 1.0) << "step " << s << " pose " << k;
          else EXPECT_LT(r, 0.99) << "step " << s << " pose " << k;
        }
        history.record(q);
      }
    }
  }
}

TEST(SprintMirror, ModelWithoutATwinIsRefused) {
  const base::Json model = base::Json::parse(R"({
    "name": "one_sided", "standing_root_height": 0.1,
    "bodies": [
      {"name": "base", "mass": 1, "geoms": [{"type": "sphere", "radius": 0.1}]},
      {"name": "arm", "parent": "base", "mass": 0.1, "geoms": [{"type": "sphere", "radius": 0.02}],
       "joints": [{"name": "left_spin", "type": "revolute", "axis": [0, 0, 1], "torque_limit": 1}]}]})");
  const sim::ModelPtr one_sided = sim::CharacterModel::from_json(model, "test model");
  EXPECT_THROW(Mirror{*one_sided}, base::UserError);
}

}  // namespace
}  // namespace podium::tasks::sprint
