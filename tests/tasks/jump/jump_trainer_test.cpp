// The trial loop's curriculum on a scripted score sequence (thesis §3.6.1, Table 3.1): z rises by
// Δz when the accumulated scores exceed R_T and not before, every copy moves with it, and the
// copies are rebuilt (same learner) when f_control(ρ(z)) changes.
#include <gtest/gtest.h>

#include "train_jump.h"

namespace podium::tasks::jump {
namespace {

TrainSettings small() {
  TrainSettings s;
  s.ppo_preset = "quick";
  s.ppo = {{"hidden", {8}}, {"rollout_steps", 2}, {"epochs", 1}, {"minibatch_size", 4}};
  s.copies = 2;
  s.curriculum = difficulty_curriculum(JumpKind::high_jump);  // 0.50 m, Δz 1 cm, R_T 30
  return s;
}

// The observation ends with z (jump_env.h).
double observed_z(learn::VecEnv& envs, std::size_t i) { return envs.observation(i).back(); }

TEST(JumpTrainer, AdvancesWhenTheScoresExceedRTAndNotBefore) {
  JumpTrainer t(small(), 1, {}, 0.5);
  EXPECT_FALSE(t.feed(10.0));
  EXPECT_FALSE(t.feed(10.0));
  EXPECT_FALSE(t.feed(10.0));  // 30 is not above R_T = 30
  EXPECT_TRUE(t.feed(0.5));
  EXPECT_NEAR(t.z(), 0.51, 1e-12);
  EXPECT_FALSE(t.feed(29.0));  // the accumulator restarted at the advance
  // Still 10 Hz (ρ = 0.02): the copies moved in place; their next observation shows the new bar.
  EXPECT_EQ(t.rebuilds(), 0);
  EXPECT_EQ(t.control_hz(), 10.0);
  t.learner().train_until(t.envs(), t.learner().env_steps() + 1);
  for (std::size_t i = 0; i < t.envs().size(); ++i) EXPECT_NEAR(observed_z(t.envs(), i), 0.51, 1e-12);
}

TEST(JumpTrainer, RebuildsTheCopiesWhenTheControlRateChanges) {
  JumpTrainer t(small(), 1, {}, 0.5);
  const std::vector<float> before = t.learner().parameters();
  EXPECT_TRUE(t.feed(31.0));  // 0.51 m: ρ = 0.02, 10.4 Hz → 10 Hz
  EXPECT_TRUE(t.feed(31.0));  // 0.52 m: 10.8 Hz → 10 Hz
  EXPECT_EQ(t.rebuilds(), 0);
  EXPECT_TRUE(t.feed(31.0));  // 0.53 m: 11.2 Hz → 12 Hz, the nearest divisor of 600
  EXPECT_EQ(t.rebuilds(), 1);
  EXPECT_EQ(t.control_hz(), 12.0);
  EXPECT_NEAR(t.z_built(), 0.53, 1e-12);
  for (std::size_t i = 0; i < t.envs().size(); ++i) EXPECT_NEAR(observed_z(t.envs(), i), 0.53, 1e-12);
  EXPECT_EQ(t.learner().parameters(), before);  // the same learner goes on
  t.learner().train_until(t.envs(), t.learner().env_steps() + 1);  // and trains on the new copies
  EXPECT_TRUE(t.feed(31.0));  // 0.54 m: 11.6 Hz → 12 Hz, no rebuild
  EXPECT_EQ(t.rebuilds(), 1);
}

TEST(JumpTrainer, FreezesAtZFreeze) {
  TrainSettings s = small();
  s.z_freeze_m = 0.52;
  JumpTrainer t(s, 1, {}, 0.5);
  t.feed(31.0);
  EXPECT_FALSE(t.frozen());
  t.feed(31.0);
  EXPECT_TRUE(t.frozen());
}

}  // namespace
}  // namespace podium::tasks::jump
