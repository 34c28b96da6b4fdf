// The jump's training stage on a scripted score sequence (thesis §3.6.1, Table 3.1): z rises by
// Δz when the accumulated scores exceed R_T and not before, every copy moves with it, and the
// copies are rebuilt (the learner trains on) when f_control(ρ(z)) changes; and a whole trial on
// the driver resumed across such a rebuild.
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "process.h"
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

// The stage with its copies built at the curriculum's start, and a learner for them.
struct Built {
  JumpStage stage;
  std::unique_ptr<learn::Learner> learner;
  explicit Built(const TrainSettings& s) : stage(s, 1, {}) {
    stage.build(nullptr);
    learner = learn::make_learner(stage.learner_spec(), stage.envs().observation_space(), stage.envs().action_space(), 2);
  }
  void train_one_iteration() { learner->train_until(stage.envs(), learner->env_steps() + 1); }
};

TEST(JumpStage, AdvancesWhenTheScoresExceedRTAndNotBefore) {
  Built b(small());
  JumpStage& t = b.stage;
  EXPECT_FALSE(t.feed(10.0));
  EXPECT_FALSE(t.feed(10.0));
  EXPECT_FALSE(t.feed(10.0));  // 30 is not above R_T = 30
  EXPECT_TRUE(t.feed(0.5));
  EXPECT_NEAR(t.z(), 0.51, 1e-12);
  EXPECT_FALSE(t.feed(29.0));  // the accumulator restarted at the advance
  // Still 10 Hz (ρ = 0.02): the copies moved in place; their next observation shows the new bar.
  EXPECT_EQ(t.rebuilds(), 0);
  EXPECT_EQ(t.control_hz(), 10.0);
  b.train_one_iteration();
  for (std::size_t i = 0; i < t.envs().size(); ++i) EXPECT_NEAR(observed_z(t.envs(), i), 0.51, 1e-12);
}

TEST(JumpStage, RebuildsTheCopiesWhenTheControlRateChanges) {
  Built b(small());
  JumpStage& t = b.stage;
  EXPECT_EQ(t.checkpoint_tag(), "10hz");
  EXPECT_TRUE(t.feed(31.0));  // 0.51 m: ρ = 0.02, 10.4 Hz → 10 Hz
  EXPECT_TRUE(t.feed(31.0));  // 0.52 m: 10.8 Hz → 10 Hz
  EXPECT_EQ(t.rebuilds(), 0);
  EXPECT_TRUE(t.feed(31.0));  // 0.53 m: 11.2 Hz → 12 Hz, the nearest divisor of 600
  EXPECT_EQ(t.rebuilds(), 1);
  EXPECT_EQ(t.control_hz(), 12.0);
  EXPECT_NEAR(t.z_built(), 0.53, 1e-12);
  EXPECT_EQ(t.checkpoint_tag(), "12hz");  // a checkpoint file of its own
  EXPECT_EQ(t.build_state(), (base::Json{{"z_built_m", t.z_built()}}));
  for (std::size_t i = 0; i < t.envs().size(); ++i) EXPECT_NEAR(observed_z(t.envs(), i), 0.53, 1e-12);
  b.train_one_iteration();    // the learner trains on the new copies
  EXPECT_TRUE(t.feed(31.0));  // 0.54 m: 11.6 Hz → 12 Hz, no rebuild
  EXPECT_EQ(t.rebuilds(), 1);
}

TEST(JumpStage, FreezesAtZFreeze) {
  TrainSettings s = small();
  s.z_freeze_m = 0.52;
  Built b(s);
  b.stage.feed(31.0);
  EXPECT_FALSE(b.stage.finished());
  EXPECT_NEAR(b.stage.progress(), 0.5, 1e-9);
  b.stage.feed(31.0);
  EXPECT_TRUE(b.stage.finished());
}

// A whole trial whose bar rises at every iteration (R_T below any score): its copies are rebuilt
// at 12 Hz at the third iteration (0.53 m). Interrupted after the fourth, the next attempt finds
// the 12 Hz checkpoint (the 10 Hz one removed), builds its copies at the z they were built at,
// trains only the two iterations left and ends exactly where the uninterrupted trial ends.
struct TrialRecord {
  std::map<std::pair<std::string, double>, double> metrics;  // a resent point overwrites itself; no time/ series
  int progress_calls = 0;
  character::Reporter reporter() {
    return {[this](const std::string& name, double step, double value) {
              if (name.rfind("time/", 0) != 0) metrics[{name, step}] = value;
            },
            [this](double) { ++progress_calls; }};
  }
};

JumpOutcome run_trial(const TrainSettings& s, const std::filesystem::path& dir, const std::atomic<bool>* cancel,
                      const character::Reporter& reporter) {
  return run_jump_trial(s, {}, {.seed = 7, .work_dir = dir, .cancel = cancel, .report = reporter});
}

TEST(JumpTrial, ResumesAcrossAControlRateRebuild) {
  TrainSettings s = small();
  s.env.sim_hz = 120;  // divisible by 10 and 12
  s.curriculum.threshold = -1e9;
  s.z_freeze_m = 0.0;
  s.total_samples = 6 * 2 * 2;  // 6 iterations of 2 steps × 2 copies
  s.eval_every = 2;
  s.eval.jumps = 1;
  s.final_jumps = 2;
  s.checkpoint_every = 1;
  const testing::TempDir whole, split;

  TrialRecord a;
  const JumpOutcome full = run_trial(s, whole.path(), nullptr, a.reporter());
  ASSERT_NEAR(full.z_reached_m, 0.56, 1e-9);
  ASSERT_EQ(a.metrics.at({"curriculum/control_hz", 12.0}), 12.0);  // rebuilt by sample 12 (iteration 3)

  TrialRecord b;
  std::atomic<bool> cancel{false};
  character::Reporter first = b.reporter();
  const auto record = first.metric;
  first.metric = [&](const std::string& name, double step, double value) {
    record(name, step, value);
    if (name == "curriculum/z_m" && value > 0.535) cancel = true;  // after iteration 4's checkpoint
  };
  EXPECT_THROW(run_trial(s, split.path(), &cancel, first), std::runtime_error);
  EXPECT_TRUE(std::filesystem::exists(split / "training_12hz.ckpt"));
  EXPECT_TRUE(std::filesystem::exists(split / "training_12hz.json"));  // the z its copies were built at
  EXPECT_FALSE(std::filesystem::exists(split / "training_10hz.ckpt"));
  EXPECT_FALSE(std::filesystem::exists(split / "training_10hz.json"));

  b.progress_calls = 0;
  const JumpOutcome resumed = run_trial(s, split.path(), nullptr, b.reporter());
  EXPECT_EQ(b.progress_calls, 1 + 2 + 1);  // before the loop, iterations 5 and 6, the end
  EXPECT_EQ(resumed.samples, full.samples);
  EXPECT_EQ(resumed.levels, full.levels);
  EXPECT_EQ(resumed.z_reached_m, full.z_reached_m);
  EXPECT_EQ(resumed.final_bar.return_mean, full.final_bar.return_mean);
  EXPECT_EQ(resumed.final_bar.mean_offset_l1, full.final_bar.mean_offset_l1);
  EXPECT_EQ(resumed.start_bar.mean_offset_l1, full.start_bar.mean_offset_l1);
  EXPECT_EQ(b.metrics, a.metrics);
}

}  // namespace
}  // namespace podium::tasks::jump
