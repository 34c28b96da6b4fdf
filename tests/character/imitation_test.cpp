// DeepMimic-style imitation (character/imitation.h) on hand-made states of the athlete: each term
// is 1 on the reference and falls with a deviation exactly as its kernel's closed form; RSI draws
// frames uniformly (χ² with a fixed seed); early termination fires at its threshold.
#include "podium/character/imitation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/character/actions.h"
#include "podium/character/frames.h"

namespace podium::character {
namespace {

// A 10-frame clip at 30 Hz: the athlete running forward at 3 m/s, its right knee and left hip swinging.
std::shared_ptr<const Clip> running_clip(bool loop = false) {
  auto clip = std::make_shared<Clip>();
  clip->model = sim::load_shipped_model("athlete");
  clip->loop = loop;
  const sim::CharacterModel& m = *clip->model;
  for (int f = 0; f < 10; ++f) {
    const double t = f / 30.0;
    Eigen::VectorXd q = m.standing_pose();
    q(0) = 3.0 * t;
    q(2) += 0.05;  // clear of the ground: a reference start raises a pose that would start in it
    q(m.link("right_knee").q_index) = -0.3 - 0.4 * std::sin(6.0 * t);
    set_quat(q, m.link("left_hip").q_index, exp_map(Eigen::Vector3d(0.0, 0.5 * std::sin(6.0 * t), 0.0)));
    clip->times_s.push_back(t);
    clip->poses.push_back(q);
  }
  return clip;
}

constexpr double kT = 4.0 / 30.0;  // a frame's time

TEST(Imitation, EveryTermIsOneOnTheReference) {
  const ImitationReference ref(running_clip());
  for (double t : {0.0, kT, 0.1, 0.25}) {
    const ImitationTerms terms = ref.terms(ref.pose(t), ref.velocity(t), t);
    EXPECT_DOUBLE_EQ(terms.pose, 1.0);
    EXPECT_DOUBLE_EQ(terms.velocity, 1.0);
    EXPECT_NEAR(terms.end_effector, 1.0, 1e-12);
    EXPECT_NEAR(terms.com, 1.0, 1e-12);
    EXPECT_NEAR(terms.total, 1.0, 1e-12);  // DeepMimic's weights sum to 1
  }
}

// DeepMimic's joint weights on the athlete's 13 links (the wrists, weight 0, are not links): they
// sum to 4.8, so a joint of DiffWeight w counts w / 4.8 of its squared error.
constexpr double kWeightSum = 4.8;

TEST(Imitation, PoseTermFallsAsExpOfMinusTwoTimesTheWeightedSquaredAngle) {
  const ImitationReference ref(running_clip());
  const sim::CharacterModel& m = *ref.clip().model;
  for (double d : {0.05, 0.2, 0.5, 1.0}) {
    Eigen::VectorXd q = ref.pose(kT);
    q(m.link("right_knee").q_index) += d;  // a hinge of weight 0.3: error d²
    EXPECT_NEAR(ref.terms(q, ref.velocity(kT), kT).pose, std::exp(-2.0 * 0.3 / kWeightSum * d * d), 1e-12) << d;
    // And a ball joint (weight 0.5) turned by d about a tilted axis.
    const int hip = m.link("right_hip").q_index;
    set_quat(q, hip, quat_at(q, hip) * exp_map(d * Eigen::Vector3d(1.0, 1.0, 0.0).normalized()));
    EXPECT_NEAR(ref.terms(q, ref.velocity(kT), kT).pose, std::exp(-2.0 * (0.3 + 0.5) / kWeightSum * d * d), 1e-9) << d;
    // The report's per-joint error is unweighted: √(2d² / 13).
    EXPECT_NEAR(ref.errors(q, ref.velocity(kT), kT).pose_rms_rad, std::sqrt(2.0 * d * d / 13.0), 1e-9) << d;
  }
  // The root's orientation counts as a joint, of weight 1.
  Eigen::VectorXd q = ref.pose(kT);
  set_quat(q, 3, quat_at(q, 3) * exp_map(Eigen::Vector3d(0.0, 0.0, 0.3)));
  EXPECT_NEAR(ref.terms(q, ref.velocity(kT), kT).pose, std::exp(-2.0 * 0.09 / kWeightSum), 1e-9);
}

TEST(Imitation, WithoutNamedWeightsEveryJointCountsTheSame) {
  ImitationWeights uniform;
  uniform.deepmimic_joint_weights = false;
  const ImitationReference ref(running_clip(), uniform);
  const sim::CharacterModel& m = *ref.clip().model;
  ASSERT_EQ(m.links().size(), 13u);
  Eigen::VectorXd q = ref.pose(kT);
  q(m.link("right_knee").q_index) += 0.4;
  EXPECT_NEAR(ref.terms(q, ref.velocity(kT), kT).pose, std::exp(-2.0 * 0.16 / 13.0), 1e-12);
}

TEST(Imitation, VelocityTermFallsAsExpOfMinusATenthOfTheWeightedSquaredRateError) {
  const ImitationReference ref(running_clip());
  const sim::CharacterModel& m = *ref.clip().model;
  for (double d : {0.5, 2.0, 5.0}) {
    Eigen::VectorXd qd = ref.velocity(kT);
    qd(m.link("left_elbow").v_index) += d;  // weight 0.2
    qd(1) -= d;                             // the root's ω_y, weight 1
    const double expected = std::exp(-0.1 * (0.2 + 1.0) / kWeightSum * d * d);
    EXPECT_NEAR(ref.terms(ref.pose(kT), qd, kT).velocity, expected, 1e-12) << d;
    qd(3) += 10.0;  // the root's linear velocity is not in r_v
    EXPECT_NEAR(ref.terms(ref.pose(kT), qd, kT).velocity, expected, 1e-12) << d;
  }
}

TEST(Imitation, EndEffectorsCountFromTheirRootAndTheComInTheWorld) {
  const ImitationReference ref(running_clip());
  const std::size_t effectors = ref.clip().model->end_effector_bodies().size();
  ASSERT_EQ(effectors, 4u);  // hands and feet
  const ImitationWeights w;
  for (double d : {0.01, 0.05, 0.2}) {
    Eigen::VectorXd q = ref.pose(kT);
    q.head<3>() += d * Eigen::Vector3d(0.6, 0.8, 0.0);  // the whole body moved by d along the ground
    ImitationTerms terms = ref.terms(q, ref.velocity(kT), kT);
    EXPECT_DOUBLE_EQ(terms.pose, 1.0);
    EXPECT_NEAR(terms.end_effector, 1.0, 1e-12) << d;  // from the root: unmoved
    EXPECT_NEAR(terms.com, std::exp(-10.0 * d * d), 1e-9) << d;
    EXPECT_NEAR(terms.total, w.pose + w.velocity + w.end_effector + w.com * terms.com, 1e-12);
    q.z() += d;  // and raised by d: every effector's height above the ground is d off
    terms = ref.terms(q, ref.velocity(kT), kT);
    EXPECT_NEAR(terms.end_effector, std::exp(-10.0 * static_cast<double>(effectors) * d * d), 1e-9) << d;
    EXPECT_NEAR(terms.com, std::exp(-10.0 * 2.0 * d * d), 1e-9) << d;
  }
  // Turned about the vertical with its root, the body's effectors are where the reference's are.
  Eigen::VectorXd q = ref.pose(kT);
  set_quat(q, 3, exp_map(Eigen::Vector3d(0.0, 0.0, 0.7)) * quat_at(q, 3));
  EXPECT_NEAR(ref.terms(q, ref.velocity(kT), kT).end_effector, 1.0, 1e-9);
}

TEST(Imitation, TermsAreTheWeightedKernelsOfTheErrors) {
  const TrackingErrors e{0.3, 4.0, 0.02, 0.05};
  const ImitationTerms t = imitation_terms(e);
  EXPECT_DOUBLE_EQ(t.pose, std::exp(-2.0 * 0.3));
  EXPECT_DOUBLE_EQ(t.velocity, std::exp(-0.1 * 4.0));
  EXPECT_DOUBLE_EQ(t.end_effector, std::exp(-10.0 * 0.02));
  EXPECT_DOUBLE_EQ(t.com, std::exp(-10.0 * 0.05));
  EXPECT_DOUBLE_EQ(t.total, 0.65 * t.pose + 0.1 * t.velocity + 0.15 * t.end_effector + 0.1 * t.com);
  ImitationWeights only_pose;
  only_pose.pose = 1.0, only_pose.velocity = only_pose.end_effector = only_pose.com = 0.0;
  EXPECT_DOUBLE_EQ(imitation_terms(e, only_pose).total, t.pose);
}

TEST(Imitation, PhaseRunsFromZeroToOneAndWrapsWhenTheClipLoops) {
  const ImitationReference once(running_clip());
  const double T = once.clip().duration_s();
  EXPECT_DOUBLE_EQ(once.phase(0.0), 0.0);
  EXPECT_DOUBLE_EQ(once.phase(T / 4), 0.25);
  EXPECT_DOUBLE_EQ(once.phase(2 * T), 1.0);
  const ImitationReference looping(running_clip(true));
  EXPECT_NEAR(looping.phase(T + T / 4), 0.25, 1e-12);
}

// χ² of the drawn frames against the uniform over [first, last], fixed seed (a test of the
// distribution, not of a timing).
double chi_squared(const std::vector<int>& counts, double expected) {
  double x = 0.0;
  for (int c : counts) x += (c - expected) * (c - expected) / expected;
  return x;
}

TEST(ReferenceStateStart, DrawsFramesUniformly) {
  const auto clip = running_clip();
  const ReferenceStateStart all;
  base::Rng rng(7);
  std::vector<int> counts(clip->size(), 0);
  const int n = 20000;
  for (int i = 0; i < n; ++i) ++counts[all.draw_frame(*clip, rng)];
  // 9 degrees of freedom: P(χ² > 27.88) = 0.001.
  EXPECT_LT(chi_squared(counts, n / 10.0), 27.88);
  for (int c : counts) EXPECT_GT(c, 0);

  const ReferenceStateStart range(0.0, 2, 6);  // frames 2..6 only
  std::vector<int> in_range(clip->size(), 0);
  for (int i = 0; i < n; ++i) ++in_range[range.draw_frame(*clip, rng)];
  EXPECT_EQ(in_range[0] + in_range[1] + in_range[7] + in_range[8] + in_range[9], 0);
  // 4 degrees of freedom: P(χ² > 18.47) = 0.001.
  EXPECT_LT(chi_squared({in_range.begin() + 2, in_range.begin() + 7}, n / 5.0), 18.47);
  EXPECT_THROW(ReferenceStateStart(0.0, 5, 3).draw_frame(*clip, rng), base::UserError);
  EXPECT_THROW(ReferenceStateStart(0.0, 0, 10).draw_frame(*clip, rng), base::UserError);
}

CharacterEnvParts imitation_parts(const std::shared_ptr<const Clip>& clip, const std::shared_ptr<const ImitationReference>& ref) {
  CharacterEnvParts parts;
  parts.model = clip->model;
  parts.world.sim_hz = 300.0, parts.world.control_hz = 30.0;
  parts.action = std::make_unique<TargetActions>(clip->model, sim::Control::spd_maba);
  parts.observation.push_back(std::make_unique<ReferencePhase>(ref));
  parts.start = std::make_unique<ReferenceStateStart>();
  parts.reward = [ref](const CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    out.reward = imitation_terms(ref->errors(env), ref->weights()).total;
  };
  parts.reference = clip;
  return parts;
}

TEST(ReferenceStateStart, StartsAtTheDrawnFrameWithItsClockAndPhase) {
  const auto clip = running_clip();
  const auto ref = std::make_shared<ImitationReference>(clip);
  CharacterEnv env(imitation_parts(clip, ref));
  env.seed(3);
  std::vector<double> obs;
  std::vector<int> seen(clip->size(), 0);
  for (int episode = 0; episode < 40; ++episode) {
    env.reset(obs);
    const double t = env.reference_time_s();
    const auto f = static_cast<std::size_t>(std::lround(t * 30.0));
    ASSERT_LT(f, clip->size());
    EXPECT_DOUBLE_EQ(t, clip->times_s[f]);  // a frame's own time
    ++seen[f];
    EXPECT_LT((env.world().data().q - clip->poses[f]).norm(), 1e-9);  // its pose (no noise)
    EXPECT_DOUBLE_EQ(obs[0], ref->phase(t));
    EXPECT_NEAR(ref->terms(env.world().data().q, env.world().data().qd, t).total, 1.0, 1e-6);
  }
  EXPECT_GE(std::count_if(seen.begin(), seen.end(), [](int c) { return c > 0; }), 8);
}

TEST(EarlyTermination, FiresAtTheComThresholdAndOnAFall) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  EarlyTermination rule;
  rule.fall_bodies = fall_bodies_except(*model, {"left_foot", "right_foot"});
  rule.max_com_deviation_m = 0.5;
  EXPECT_EQ(rule.fall_bodies.size(), model->bodies().size() - 2);
  sim::Observation features;
  TrackingErrors e;
  const ImitationTerms ok;
  e.com = 0.49 * 0.49;
  EXPECT_EQ(early_termination(rule, features, e, ok), Termination::none);
  e.com = 0.5 * 0.5;
  EXPECT_EQ(early_termination(rule, features, e, ok), Termination::deviated);
  e.com = 0.0;
  features.contacts = {{model->find_body("right_foot"), sim::Contact::Partner::ground, -1}};
  EXPECT_EQ(early_termination(rule, features, e, ok), Termination::none);  // a foot may touch
  features.contacts.push_back({model->find_body("chest"), sim::Contact::Partner::ground, -1});
  EXPECT_EQ(early_termination(rule, features, e, ok), Termination::fell);
  features.contacts = {{model->find_body("chest"), sim::Contact::Partner::prop, 0}};
  EXPECT_EQ(early_termination(rule, features, e, ok), Termination::none);  // the ground only

  rule.min_pose_reward = 0.2;
  ImitationTerms low;
  low.pose = 0.2;
  EXPECT_EQ(early_termination(rule, features, e, low), Termination::deviated);
  low.pose = 0.2000001;
  EXPECT_EQ(early_termination(rule, features, e, low), Termination::none);
  EXPECT_THROW(fall_bodies_except(*model, {"tail"}), base::UserError);
}

TEST(Imitation, RejectsAClipWithoutFrames) {
  auto clip = std::make_shared<Clip>();
  EXPECT_THROW(ImitationReference{clip}, base::UserError);
  clip->model = sim::load_shipped_model("athlete");
  clip->times_s = {0.0};
  clip->poses = {clip->model->standing_pose()};
  EXPECT_THROW(ImitationReference{clip}, base::UserError);
}

}  // namespace
}  // namespace podium::character
