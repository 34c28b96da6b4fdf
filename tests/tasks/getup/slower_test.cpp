// The Slower and Evaluate stages' parts on real Bullet and a real
// (untrained) libtorch policy: retiming τ_fast by κ, the ε-RSI start distribution, a π_weak that
// never rises failing with its reason, exact resume of a Slower episode, §8.3's pause, and the
// strategy features on scripted states.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "evaluate.h"
#include "podium/base/error.h"
#include "podium/learn/learner.h"
#include "podium/learn/vec_env.h"
#include "process.h"
#include "strategy_features.h"

namespace podium::tasks::getup {
namespace {

namespace fs = std::filesystem;

EnvSettings short_falls() {
  EnvSettings s;
  s.fall.control_steps = 20;
  return s;
}

// An untrained SAC policy for the get-up env, exported as TorchScript (π_weak's file format),
// once per test process into a folder removed at its exit.
fs::path untrained_weak_policy() {
  static const podium::testing::TempDir dir;
  fs::path path = dir / "weak.pt";
  if (fs::exists(path)) return path;
  GetupEnv env(short_falls(), std::make_shared<double>(1.0), false);
  const base::Json spec = {{"algorithm", "sac"}, {"preset", "quick"}, {"config", {{"hidden", {8, 8}}}}};
  learn::make_learner(spec, env.observation_space(), env.action_space(), 1)->export_torchscript(path);
  return path;
}

std::shared_ptr<const learn::FrozenPolicy> weak_policy() {
  return std::make_shared<const learn::FrozenPolicy>(untrained_weak_policy());
}

// A hand-made τ_fast of humanoid21: the knees bend a little more each frame.
FastRollout knee_bend(int steps) {
  const auto model = sim::load_shipped_model("humanoid21");
  const int knee = model->link("knee_right").q_index;
  const int hip = model->link("hip_y_right").v_index;
  FastRollout f;
  for (int i = 0; i <= steps; ++i) {
    Eigen::VectorXd q = model->standing_pose();
    q(knee) = -0.1 * i;
    Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
    qd(hip) = 1.0 + i;
    f.q.push_back(q);
    f.qd.push_back(qd);
    f.com_height_m.push_back(0.2 + 0.1 * i);
    f.torso_up.emplace_back(0.0, 0.1 * i, 1.0);
  }
  return f;
}

TEST(SlowReference, RetimedByKappaItLastsTOverKappaAndPassesThroughEveryFrame) {
  const auto model = sim::load_shipped_model("humanoid21");
  const double dt = 1.0 / 40.0, kappa = 0.4;
  const FastRollout fast = knee_bend(6);
  const SlowReference slow(fast, kappa, dt, model, model->standing_pose(), 1.0);
  EXPECT_NEAR(slow.rise_s(), 6 * dt / kappa, 1e-12);  // T/κ
  const int hip = model->link("hip_y_right").v_index;
  for (int i = 0; i <= 6; ++i) {
    const double t = i * dt / kappa;
    EXPECT_LT((slow.clip()->sample(t).tail(model->nq() - 7) - fast.q[i].tail(model->nq() - 7)).norm(), 1e-12) << "frame " << i;
    EXPECT_NEAR(slow.com_height_m(t), fast.com_height_m[i], 1e-12);
    EXPECT_NEAR(slow.torso_up(t).y(), fast.torso_up[i].y(), 1e-12);
    EXPECT_NEAR(slow.hip_velocity(t)(0), kappa * fast.qd[i](hip), 1e-12);  // slowed by κ
  }
  // Between frames: interpolated; after the rise: the standing pose and its COM height, upright.
  EXPECT_NEAR(slow.com_height_m(0.5 * dt / kappa), 0.25, 1e-12);
  EXPECT_EQ(slow.com_height_m(slow.rise_s() + 2 * dt), 1.0);
  EXPECT_EQ(slow.torso_up(slow.rise_s() + 2 * dt), Eigen::Vector3d::UnitZ());
  const Eigen::VectorXd after = slow.clip()->sample(slow.rise_s() + 2 * dt);
  EXPECT_LT((after.tail(model->nq() - 7) - model->standing_pose().tail(model->nq() - 7)).norm(), 1e-12);
}

TEST(SlowerEnv, EpsilonRsiStartsAtTheBeginningWithProbabilityEpsilonElseUniformly) {
  base::Rng rng(7);
  const int n = 10, draws = 200000;
  const double epsilon = 0.2;
  std::vector<int> counts(n, 0);
  for (int i = 0; i < draws; ++i) ++counts[static_cast<std::size_t>(rsi_start_step(rng, n, epsilon))];
  // P(0) = ε + (1 − ε)/n; P(k > 0) = (1 − ε)/n. Bounds at 5 standard deviations.
  const auto expect_share = [&](int k, double p) {
    const double sd = std::sqrt(p * (1 - p) / draws);
    EXPECT_NEAR(counts[static_cast<std::size_t>(k)] / double(draws), p, 5 * sd) << "step " << k;
  };
  expect_share(0, epsilon + (1 - epsilon) / n);
  for (int k = 1; k < n; ++k) expect_share(k, (1 - epsilon) / n);
  EXPECT_EQ(rsi_start_step(rng, 0, 0.0), 0);  // no step to choose from
}

TEST(SlowerEnv, APolicyThatNeverRisesFailsWithThatReason) {
  SlowerSettings s;
  s.max_rise_steps = 15;
  s.rise_attempts = 2;
  SlowerEnv env(short_falls(), s, weak_policy(), 1.0, std::nullopt);  // untrained: lies on the ground
  env.seed(1);
  std::vector<double> observation;
  try {
    env.reset(observation);
    FAIL() << "an untrained π_weak rose within 15 steps";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("never lifted the head origin above 1.4"), std::string::npos) << e.what();
  }
}

// With τ_fast's end at 0.01 m it ends at its first steps (the lying head origin is higher), so an
// untrained π_weak gives a reference: enough to check the episode's mechanics.
SlowerSettings immediate_rise() {
  SlowerSettings s;
  s.reference_end_m = 0.01;
  s.balance_steps = 12;
  return s;
}

TEST(SlowerEnv, AnEpisodeTracksThenStandsAndEndsAtTOverKappaPlusTheBalanceSteps) {
  const double kappa = 0.25;
  SlowerEnv env(short_falls(), immediate_rise(), weak_policy(), 1.0, kappa);
  env.seed(3);
  std::vector<double> observation;
  env.reset(observation);
  const auto& ref = env.reference_motion();
  ASSERT_GE(ref.fast().steps(), 1);
  const int rise_steps = static_cast<int>(std::lround(ref.rise_s() * 40.0));
  EXPECT_EQ(rise_steps, static_cast<int>(std::lround(ref.fast().steps() / kappa)));
  EXPECT_EQ(observation.size(), env.observation_space().size());
  learn::StepResult step;
  int steps = 0;
  const std::vector<double> zero(env.action_space().size(), 0.0);
  double gap_at_last_rise_step = 0.0;
  do {
    env.step(zero, step);
    ++steps;
    EXPECT_EQ(env.standing_phase(), steps > rise_steps) << "step " << steps;
    if (!env.standing_phase()) gap_at_last_rise_step = ref.com_height_m(env.reference_time_s()) - env.features().com.z();
  } while (!step.terminated && !step.truncated);
  if (step.truncated) EXPECT_EQ(steps, rise_steps + 12);
  else EXPECT_LT(env.features().com.z(), 0.5);  // the only way the standing phase ends early
  EXPECT_GT(env.mean_com_error_m(), 0.0);
  // Every rise step counted, the terminating one too: the whole rise, or the share before the end.
  EXPECT_DOUBLE_EQ(env.tracked_fraction(), std::min(steps, rise_steps) / static_cast<double>(rise_steps));
  EXPECT_DOUBLE_EQ(env.end_com_gap_m(), gap_at_last_rise_step);
}

// The head origin's height in each frame of τ_fast.
std::vector<double> head_origins(const FastRollout& fast, const sim::ModelPtr& model) {
  std::vector<double> heights;
  sim::CharacterData data(*model);
  for (const Eigen::VectorXd& q : fast.q) {
    data.q = q;
    sim::forward_kinematics(*model, data);
    heights.push_back(sim::body_point(*model, data, model->head_body(), Eigen::Vector3d::Zero()).z());
  }
  return heights;
}

// τ_fast ends reference_end_extra_steps after the first step whose head origin passes the
// configured height (the seed repository: 1 step after 1.4 m). The untrained π_weak's head moves
// about; a height just under a new highest head origin ends τ_fast at that frame plus the extra step.
TEST(SlowerEnv, TheReferenceEndsAtTheFirstStepPastTheConfiguredHeight) {
  SlowerSettings wide = immediate_rise();
  wide.reference_end_extra_steps = 40;  // the first step passes 0.01 m: 41 frames after the fall's end
  SlowerEnv first(short_falls(), wide, weak_policy(), 1.0, 0.5);
  first.seed(7);
  std::vector<double> observation;
  first.reset(observation);
  const auto model = first.world().model_ptr();
  const std::vector<double> h = head_origins(first.reference_motion().fast(), model);
  ASSERT_EQ(h.size(), 42u);
  int record = -1;  // the first step k ≥ 2 above every earlier step's head origin
  for (int k = 2; k < static_cast<int>(h.size()) && record < 0; ++k)
    if (h[k] > *std::max_element(h.begin() + 1, h.begin() + k)) record = k;
  ASSERT_GT(record, 0) << "the untrained π_weak's head never rose above its first step's";
  const double below = *std::max_element(h.begin() + 1, h.begin() + record);
  for (const int extra : {0, 1}) {
    SlowerSettings s = immediate_rise();
    s.reference_end_m = 0.5 * (below + h[record]);
    s.reference_end_extra_steps = extra;
    SlowerEnv env(short_falls(), s, weak_policy(), 1.0, 0.5);
    env.seed(7);  // the same fall, the same π_weak: the same steps
    env.reset(observation);
    const std::vector<double> ended = head_origins(env.reference_motion().fast(), model);
    EXPECT_EQ(env.reference_motion().fast().steps(), record + extra) << "extra " << extra;
    EXPECT_GT(ended[record], s.reference_end_m);
    for (int k = 1; k < record; ++k) EXPECT_LE(ended[k], s.reference_end_m) << "step " << k;
  }
}

// The standing phase's target pose, COM height and gains are the configured ones, and R_balance
// reads them: a configured pose (knees bent 0.7 rad) and h'_com reach the reward as given.
TEST(SlowerEnv, TheStandingPoseAndGainsReachTheBalanceRewardAsConfigured) {
  SlowerSettings s = immediate_rise();
  for (auto& [joint, angle] : s.standing_pose)
    if (joint == "knee_right" || joint == "knee_left") angle = -0.7;
  s.standing_com_m = 0.75;
  s.standing_kd_ratio = 4.0;
  SlowerEnv env(short_falls(), s, weak_policy(), 1.0, 0.8);
  env.seed(11);
  std::vector<double> observation;
  env.reset(observation);
  const auto model = env.world().model_ptr();
  const sim::Link& knee = model->link("knee_left");
  EXPECT_EQ(env.standing_pose()(knee.q_index), -0.7);
  EXPECT_EQ(env.standing_pose()(model->link("elbow_right").q_index), -1.5795);  // the seed's, unchanged
  EXPECT_EQ(env.standing_com_m(), 0.75);
  const std::vector<double> zero(env.action_space().size(), 0.0);
  learn::StepResult step;
  int standing_steps = 0, rise_steps = 0;
  do {
    const bool standing = env.standing_phase();
    env.step(zero, step);
    // The step ran with the phase's gains: k_d = k_p/10 over the rise, k_p/standing_kd_ratio after.
    const double kp = model->torque_limits()(knee.v_index);
    EXPECT_DOUBLE_EQ(env.world().gains().kd(knee.v_index), kp / (standing ? 4.0 : 10.0));
    rise_steps += !standing;
    if (!env.standing_phase()) continue;
    ++standing_steps;
    // The PD target is q̂ (the reference's last frame) and the reward R_balance at q̂, h'_com.
    EXPECT_EQ(env.reference_motion().clip()->poses.back().tail(model->nq() - 7), env.standing_pose().tail(model->nq() - 7));
    const sim::Observation& f = env.features();
    BalanceState b;
    b.com_velocity_xy = f.com_vel.head<2>();
    b.torso_up_z = f.torso_up.z();
    b.com_height_m = f.com.z();
    b.com_height_error_m = f.com.z() - 0.75;
    const Eigen::VectorXd& q = env.world().data().q;
    for (const sim::Link& l : model->links())
      if (l.joint == sim::JointType::revolute)
        b.pose_squared_error += (q(l.q_index) - env.standing_pose()(l.q_index)) * (q(l.q_index) - env.standing_pose()(l.q_index));
    EXPECT_DOUBLE_EQ(step.reward, reward_balance(b));
  } while (!step.terminated && !step.truncated);
  // The lying body ends the standing phase at once (h_com < 0.5 m), after its reward was scored.
  EXPECT_GT(rise_steps, 0);
  EXPECT_GT(standing_steps, 0) << "the episode ended before its standing phase";
}

TEST(SlowerEnv, ASavedEpisodeResumesBitwiseInAFreshEnv) {
  SlowerEnv original(short_falls(), immediate_rise(), weak_policy(), 1.0, std::nullopt);
  original.seed(5);
  std::vector<double> observation;
  original.reset(observation);
  learn::StepResult a, b;
  const auto action = [](int t, std::size_t n) {
    std::vector<double> v(n);
    for (std::size_t j = 0; j < n; ++j) v[j] = 0.3 * std::sin(0.2 * t + static_cast<double>(j));
    return v;
  };
  for (int t = 0; t < 3; ++t) original.step(action(t, original.action_space().size()), a);
  const auto state = original.save_state();
  SlowerEnv restored(short_falls(), immediate_rise(), weak_policy(), 1.0, std::nullopt);
  restored.load_state(*state);
  EXPECT_EQ(restored.reference_motion().kappa(), original.reference_motion().kappa());
  for (int t = 3; t < 10; ++t) {
    original.step(action(t, original.action_space().size()), a);
    restored.step(action(t, restored.action_space().size()), b);
    ASSERT_EQ(a.observation, b.observation) << "step " << t;
    ASSERT_EQ(a.reward, b.reward) << "step " << t;
    if (a.terminated || a.truncated) break;
  }
}

TEST(Evaluate, APauseHoldsOneFrameWithoutVelocity) {
  const FastRollout fast = knee_bend(6);
  const FastRollout held = paused(fast, 0.5, 4);
  ASSERT_EQ(held.steps(), 10);
  for (int i = 3; i <= 7; ++i) {
    EXPECT_EQ(held.q[static_cast<std::size_t>(i)], fast.q[3]) << i;
    EXPECT_TRUE(held.qd[static_cast<std::size_t>(i)].isZero()) << i;
    EXPECT_EQ(held.com_height_m[static_cast<std::size_t>(i)], fast.com_height_m[3]) << i;
  }
  EXPECT_EQ(held.q[8], fast.q[4]);  // then the motion goes on
  EXPECT_EQ(held.q.back(), fast.q.back());
}

// Scripted states: a real fall (lying on the ground), then lying on the back in the air, then
// half up leaning back at 45°: the chest's direction at half height and the share of the rise
// each kind of body spent on the ground.
TEST(StrategyFeatures, ReadTheChestAtHalfHeightAndTheSupportingBodies) {
  GetupEnv env(short_falls(), std::make_shared<double>(1.0), false);
  const auto& model = env.model();
  StrategyRecorder recorder(model, env.readings().head_top_m, 1.2);
  std::vector<double> observation;
  env.seed(2);
  env.reset(observation);  // the fall's end
  ASSERT_LT(env.weak().head_height_m, 0.6);
  const auto touching = [&](std::initializer_list<const char*> bodies) {
    for (const char* b : bodies)
      if (env.features().touches(model.find_body(b), sim::Contact::Partner::ground)) return 1.0;
    return 0.0;
  };
  const double hands = touching({"hand_left", "hand_right", "lower_arm_left", "lower_arm_right"});
  const double knees = touching({"shin_left", "shin_right"});
  const double side = env.features().torso_up.y();
  recorder.observe(env);
  const auto pose = [&](double pitch_rad, double root_height_m) {
    Eigen::VectorXd q = model.standing_pose();
    const Eigen::Quaterniond r(Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()));
    q(2) = root_height_m;
    q(3) = r.w(), q(4) = r.x(), q(5) = r.y(), q(6) = r.z();
    env.world().reset(q, Eigen::VectorXd::Zero(model.nv()));
    env.observe(observation);
    recorder.observe(env);
  };
  pose(-std::numbers::pi / 2, 0.3);  // on the back (the front axis up), off the ground
  EXPECT_GT(env.features().torso_up.x(), 0.99);
  EXPECT_LT(env.weak().head_height_m, 0.6);
  pose(-std::numbers::pi / 4, 1.0);  // leaning back, lifted: the head passes 0.6 m and 1.2 m here
  EXPECT_GT(env.weak().head_height_m, 1.2);
  EXPECT_TRUE(env.features().contacts.empty());
  pose(-std::numbers::pi / 2, 0.3);  // after the rise: not counted
  const double counted = 3.0;
  const StrategyFeatures f = recorder.features();
  EXPECT_NEAR(f.values[0], std::sin(std::numbers::pi / 4), 1e-6);  // the chest at half height: up at 45°
  EXPECT_NEAR(f.values[1], side / counted, 1e-6);                  // the fall's lean, then none
  EXPECT_DOUBLE_EQ(f.values[2], hands / counted);
  EXPECT_DOUBLE_EQ(f.values[3], knees / counted);
  EXPECT_EQ(mean_features({f, f}).values, f.values);
}

}  // namespace
}  // namespace podium::tasks::getup
