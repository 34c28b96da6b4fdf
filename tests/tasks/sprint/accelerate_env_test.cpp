// The accelerate stage's environment side on humanoid34: the fallback start set (the crouch
// starts' last frames, just past the line, one foot down, each episode its own draw), the training
// copies' distance log, and the evaluation's dip snapshots (hand-over states with their draw that
// continue bitwise in another env).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "podium/base/rng.h"
#include "train_accelerate.h"

namespace podium::tasks::sprint {
namespace {

using base::Json;

SprintEnvSettings run_settings(const std::vector<Json>& starts) {
  SprintEnvSettings s;
  s.preset = load_sprint_preset("smoke");
  s.sim_hz = 150.0;
  s.handover_states = starts;
  return s;
}

// Targets U(−0.3, 0.3) drawn per step from a seed.
character::PolicyFn random_policy(std::uint64_t seed) {
  auto rng = std::make_shared<base::Rng>(seed);
  return [rng](std::span<const double>, std::span<double> a) {
    for (double& v : a) v = rng->uniform(-0.3, 0.3);
  };
}

TEST(SprintAccelerate, FallbackStartsAreTheCrouchStartsLastFramesAtTheLine) {
  const std::vector<Json> starts = fallback_starts("smoke", 150.0);
  ASSERT_EQ(starts.size(), 4u);  // left/right front foot × straight/bent elbow
  SprintEnv env(run_settings(starts));
  std::set<double> winds;
  for (std::uint64_t seed = 0; seed < 12; ++seed) {
    env.seed(seed);
    std::vector<double> observation;
    env.reset(observation);
    const double x = env.world().data().q(0);
    EXPECT_GT(x, 0.0);  // past the line,
    EXPECT_LT(x, 1.0);  // at the first landing's distance
    const sim::Observation& f = env.features();
    const bool left = f.touches(env.bodies().left_foot, sim::Contact::Partner::ground),
               right = f.touches(env.bodies().right_foot, sim::Contact::Partner::ground);
    EXPECT_TRUE(left != right) << "seed " << seed;  // the landing foot only
    EXPECT_EQ(env.outcome(), SprintEnv::Outcome::running);
    winds.insert(env.draw().wind_mps);
  }
  EXPECT_EQ(winds.size(), 12u);  // no draw in the states: every episode draws its own
}

TEST(SprintAccelerate, TrainingCopiesLogEachEndedEpisodesDistance) {
  SprintEnvSettings s = run_settings(fallback_starts("smoke", 150.0));
  s.log_distances = true;
  SprintEnv env(s);
  env.seed(3);
  std::vector<double> observation, action(env.action_space().size()), expected;
  const character::PolicyFn policy = random_policy(5);
  for (int episode = 0; episode < 3; ++episode) {
    env.reset(observation);
    const double start = env.world().data().q(0);
    learn::StepResult r;
    do {
      policy(observation, action);
      env.step(action, r);
      observation = r.observation;
    } while (!r.terminated && !r.truncated);
    expected.push_back(env.world().data().q(0) - start);
  }
  env.reset(observation);  // the third ends here
  const std::vector<double> logged = env.take_episode_distances();
  ASSERT_EQ(logged.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(logged[i], expected[i]) << i;
  EXPECT_TRUE(env.take_episode_distances().empty());
}

TEST(SprintAccelerate, DipSnapshotsAreTakenBeforeTheLineAndContinueBitwise) {
  AccelerateSettings a;
  a.handover_before_line_m = 9.8;  // 0.2 m on the 10 m track: every run starts past it
  SprintEnv env(run_settings(fallback_starts("smoke", 150.0)));
  const RunEvaluation e = evaluate_runs(env, random_policy(7), 3, 11, a);
  ASSERT_EQ(e.handovers.size(), 3u);
  EXPECT_EQ(e.segment_m, 10.0 / 3.0);
  EXPECT_GE(e.rise_rate, 0.0);
  EXPECT_LE(e.rise_rate, 1.0);
  // A snapshot carries its run's draw and, loaded as a start, continues bitwise in two envs.
  const Json& snap = e.handovers[1];
  ASSERT_TRUE(snap.contains("draw") && snap.contains("world") && snap.contains("step_counter"));
  SprintEnv one(run_settings({snap})), two(run_settings({snap}));
  one.seed(1), two.seed(2);
  std::vector<double> o1, o2, action(one.action_space().size(), 0.1);
  one.reset(o1), two.reset(o2);
  EXPECT_EQ(one.draw().to_json(), snap["draw"]);
  EXPECT_EQ(o1, o2);
  learn::StepResult r1, r2;
  for (int k = 0; k < 5; ++k) {
    one.step(action, r1), two.step(action, r2);
    EXPECT_EQ(r1.observation, r2.observation) << k;
    if (r1.terminated) break;
  }
  // Too far back to reach: no snapshots.
  a.handover_before_line_m = 0.0;
  EXPECT_TRUE(evaluate_runs(env, random_policy(7), 2, 11, a).handovers.empty());
}

}  // namespace
}  // namespace podium::tasks::sprint
