// The run-up environment on the authors' reference runs (skipped with the reason when
// ../shared/data/jump is absent): the reference on the athlete, the episode's start on it, the
// hand-over exactly at the take-off condition in a real rollout, and the full jump's placement.
#include "runup_env.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "jump_test_util.h"
#include "podium/character/frames.h"
#include "train_runup.h"

namespace podium::tasks::jump {
namespace {

RunupSettings settings(const std::string& file, JumpKind kind) {
  RunupSettings s;
  s.kind = kind;
  s.motion = (testing::captured_jump_dir() / "motions/beyond" / file).string();
  s.sim_hz = 150.0;
  s.takeoff_features =
      kind == JumpKind::high_jump ? std::vector<double>{1.0, -1.0, 0.5, 1.0} : std::vector<double>{0.5, -1.0, 1.0};
  return s;
}

#define SKIP_WITHOUT_DATA() \
  if (testing::captured_jump_dir().empty()) GTEST_SKIP() << "../shared/data/jump absent (PODIUM_SHARED_DIR)"

TEST(RunupEnv, ReferenceRunsStandOnTheGroundAndTakeOffOnTheRightFoot) {
  SKIP_WITHOUT_DATA();
  for (const auto& [file, kind] :
       {std::pair{"VC5_sprint__curves_03.txt", JumpKind::high_jump}, std::pair{"VC5_Run_jumpToBox_01.txt", JumpKind::obstacle}}) {
    const RunupSettings s = settings(file, kind);
    const auto clip = load_reference_run(s);
    RunupEnv env(s, clip, true);
    std::printf("%s: %zu frames at 30 Hz, %.2f s; take-off at %.3f s\n", file, clip->size(), clip->duration_s(),
                env.condition().takeoff_time_s);
    EXPECT_NEAR(clip->times_s[1], 1.0 / 30.0, 1e-12);
    EXPECT_GT(env.condition().takeoff_time_s, 0.5) << file;  // a run, not a standing start
    EXPECT_LE(env.condition().takeoff_time_s, clip->duration_s()) << file;
    EXPECT_EQ(env.full_steps(), static_cast<int>(std::lround(env.condition().takeoff_time_s * 30.0)));
    // The take-off leads into the captured jump's flight: the root rises after it (the curved
    // sprint lands and walks on after its jump; its last single support is not the take-off).
    const double t = env.condition().takeoff_time_s;
    EXPECT_GT(clip->sample(t + 0.3)(2), clip->sample(t)(2) + 0.2) << file;
  }
}

TEST(RunupEnv, StartsOnTheReferenceAndHandsOverExactlyAtTheTakeoffCondition) {
  SKIP_WITHOUT_DATA();
  RunupSettings s = settings("VC5_sprint__curves_03.txt", JumpKind::high_jump);
  s.takeoff_time_s = 0.5;  // early in the run: PD tracking alone keeps the athlete up that long
  const auto clip = load_reference_run(s);
  const character::ImitationReference reference(clip);
  RunupEnv env(s, clip, true);
  std::vector<double> obs;
  env.reset(obs);
  EXPECT_DOUBLE_EQ(env.reference_time_s(), 0.0);
  EXPECT_NEAR(reference.terms(env.world().data().q, env.world().data().qd, 0.0).total, 1.0, 1e-6);
  EXPECT_DOUBLE_EQ(obs.back(), 0.0);  // the phase
  // Residual actions of 0 (PD targets on the reference pose): the athlete follows the run until it
  // falls or hands over.
  const std::vector<double> zero(env.action_space().size(), 0.0);
  const int foot = clip->model->find_body("right_foot"), other = clip->model->find_body("left_foot");
  learn::StepResult out;
  int steps = 0;
  bool expected = false;
  do {
    env.step(zero, out);
    ++steps;
    const bool fell = env.termination() != character::Termination::none;
    expected = !fell && takeoff_reached(env.condition(), env.reference_time_s(),
                                        env.features().touches(foot, sim::Contact::Partner::ground),
                                        env.features().touches(other, sim::Contact::Partner::ground));
    EXPECT_EQ(env.handed_over(), expected) << "step " << steps;
  } while (!out.terminated && !out.truncated);
  std::printf("PD tracking: %d steps, %s at %.3f s (take-off %.3f s), r_G %.3f\n", steps,
              env.handed_over() ? "handed over" : to_string(env.termination()), env.reference_time_s(),
              env.condition().takeoff_time_s, env.task_reward());
  EXPECT_TRUE(out.terminated);  // a hand-over or an early termination ends the episode, never the step limit
  ASSERT_TRUE(env.handed_over());
  EXPECT_GE(env.reference_time_s(), 0.5 - 0.2 - 1e-9);
  EXPECT_LE(env.reference_time_s(), 0.5 + 1e-9);
  {
    EXPECT_DOUBLE_EQ(out.info[1], 1.0);
    EXPECT_DOUBLE_EQ(env.task_reward(),
                     runup_task_reward(env.target(), root_motion(env.world().data().q, env.world().data().qd)));
    EXPECT_NEAR(out.reward, 0.7 * out.info[0] + 0.3 * env.full_steps() * env.task_reward(), 1e-9);
  }
}

// runup_lead_s: the run-up begins that long before the take-off (on a frame), evaluation starts
// there and RSI draws no earlier frame; the hand-over's task term counts the shorter run's steps.
TEST(RunupEnv, ALeadStartsTheRunUpThatLongBeforeTheTakeoff) {
  SKIP_WITHOUT_DATA();
  RunupSettings s = settings("VC5_sprint__curves_03.txt", JumpKind::high_jump);
  s.lead_s = 1.0;
  const auto clip = load_reference_run(s);
  RunupEnv from_start(s, clip, true);
  const double t_off = from_start.condition().takeoff_time_s;
  const double first = std::floor((t_off - 1.0) * 30.0 + 1e-9) / 30.0;
  EXPECT_NEAR(from_start.start_time_s(), first, 1e-9);
  EXPECT_EQ(from_start.full_steps(), static_cast<int>(std::lround((t_off - first) * 30.0)));
  std::vector<double> obs;
  from_start.reset(obs);
  EXPECT_NEAR(from_start.reference_time_s(), first, 1e-9);
  EXPECT_LT((from_start.world().data().q - clip->sample(first)).norm(), 1e-9);  // no noise
  RunupEnv rsi(s, clip, false);
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    rsi.seed(seed);
    rsi.reset(obs);
    EXPECT_GE(rsi.reference_time_s(), first - 1e-9);
    EXPECT_LT(rsi.reference_time_s(), t_off);
  }
}

TEST(RunupEnv, PlacementTurnsTheHandOverStateToFacePlusXOverTheOrigin) {
  Eigen::VectorXd q = sim::load_shipped_model("athlete")->standing_pose();
  q.head<3>() = Eigen::Vector3d(4.0, -2.0, 0.9);
  character::set_quat(
      q, 3,
      Eigen::Quaterniond(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX())));
  const Placement p = place_for_jump(q);
  EXPECT_NEAR(p.q(0), 0.0, 1e-12);
  EXPECT_NEAR(p.q(1), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.q(2), 0.9);
  EXPECT_NEAR(character::heading_yaw(character::quat_at(p.q, 3).toRotationMatrix()), 0.0, 1e-12);
  EXPECT_EQ(p.q.tail(p.q.size() - 7), q.tail(q.size() - 7));  // the joints as they were
  EXPECT_LT((p.rotation * (Eigen::Vector3d(4.0, -2.0, 0.9) - p.offset) - Eigen::Vector3d(0.0, 0.0, 0.9)).norm(), 1e-12);
}

}  // namespace
}  // namespace podium::tasks::jump
