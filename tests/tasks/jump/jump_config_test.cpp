// The jump plugin's config is checked where describe() runs (at submit): each bad value is one
// error at its JSON path; the defaults are the thesis's settings.
#include <gtest/gtest.h>

#include "config_errors.h"
#include "train_jump.h"

namespace podium::tasks::jump {
namespace {

using base::Json;

TrainSettings read(const Json& config) { return base::ConfigReader::parse(config, "jump config", read_train_settings); }

std::string error_path(const Json& config) { return podium::testing::config_error_path(config, read_train_settings); }

TEST(JumpConfig, DefaultsAreTheThesisSettings) {
  const TrainSettings s = read(Json::object());
  EXPECT_EQ(s.env.sim_hz, 600.0);                 // §3.6.2
  EXPECT_EQ(learner_spec(s)["preset"], "paper");  // PpoConfig::paper() = §3.6.2
  EXPECT_EQ(s.total_samples, 12'000LL * 4096);
  EXPECT_EQ(s.z_freeze_m, 1.0);          // §3.6.1
  EXPECT_EQ(s.curriculum.initial, 0.5);  // Table 3.1, high jump
  EXPECT_EQ(s.curriculum.increment, 0.01);
  EXPECT_EQ(s.curriculum.threshold, 30.0);
  EXPECT_EQ(s.curriculum.limit, 2.0);
  EXPECT_EQ(s.final_jumps, 20);
}

TEST(JumpConfig, TheObstacleStartsAtItsOwnTableRow) {
  const TrainSettings s = read({{"kind", "obstacle"}});
  EXPECT_EQ(s.curriculum.initial, 0.05);
  EXPECT_EQ(s.curriculum.increment, 0.05);
  EXPECT_EQ(s.curriculum.threshold, 50.0);
  EXPECT_EQ(s.curriculum.limit, 2.5);
  const TrainSettings t = read({{"kind", "obstacle"}, {"difficulty_m", 0.2}, {"z_step_m", 0.1}, {"reward_threshold", 5.0}});
  EXPECT_EQ(t.curriculum.initial, 0.2);
  EXPECT_EQ(t.curriculum.increment, 0.1);
  EXPECT_EQ(t.curriculum.threshold, 5.0);
}

TEST(JumpConfig, BadValuesAreReportedAtTheirPath) {
  EXPECT_EQ(error_path({{"kind", "long_jump"}}), "kind");
  EXPECT_EQ(error_path({{"ppo_preset", "papr"}}), "ppo_preset");
  EXPECT_EQ(error_path({{"ppo", {{"rollout_step", 250}}}}), "ppo");
  EXPECT_EQ(error_path({{"threads", 32}}), "threads");  // above copies 16
  EXPECT_EQ(error_path({{"sim_hz", 150.5}}), "sim_hz");
  EXPECT_EQ(error_path({{"z_max_m", 0.3}}), "z_max_m");  // below the starting 0.5 m
  EXPECT_EQ(error_path({{"curriculum_score", "per_step"}}), "curriculum_score");
  EXPECT_EQ(error_path({{"eval_jumps", 0}}), "eval_jumps");
  EXPECT_EQ(error_path({{"takeoff_features", {1.0}}}), "takeoff_features");
  EXPECT_EQ(error_path({{"bar", 1.0}}), "bar");  // unknown keys too
}

TEST(JumpConfig, TheScoreIsTheIterationsRewardPerEpisodeOrPerSample) {
  learn::TrainStats stats;
  stats.episodes = 4, stats.mean_return = 0.5;  // two units of reward in the iteration
  EXPECT_DOUBLE_EQ(iteration_score("per_episode", stats, 64), 0.5);
  EXPECT_DOUBLE_EQ(iteration_score("per_sample", stats, 64), 2.0 / 64);
  stats.episodes = 0, stats.mean_return = std::nan("");  // no episode ended: no reward
  EXPECT_EQ(iteration_score("per_episode", stats, 64), 0.0);
}

}  // namespace
}  // namespace podium::tasks::jump
