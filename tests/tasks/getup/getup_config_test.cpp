// The getup config is checked where describe() runs (at submit): each bad value is one error at
// its JSON path.
#include <gtest/gtest.h>

#include "config_errors.h"
#include "discover_weaker.h"
#include "podium/learn/sac.h"
#include "slower.h"

namespace podium::tasks::getup {
namespace {

using base::Json;

Settings read(const Json& config) { return base::ConfigReader::parse(config, "getup config", read_settings); }

std::string error_path(const Json& config) { return podium::testing::config_error_path(config, read_settings); }

TEST(GetupConfig, DefaultsAreTheSeedsSettings) {
  const Settings s = read(Json::object());
  // The seed repository's body: humanoid_static.xml at 200 Hz, passive joints, the zero-torque fall.
  EXPECT_EQ(s.env.model, "humanoid21_seed");
  EXPECT_EQ(s.env.sim_hz, 200.0);
  EXPECT_EQ(s.env.control_hz, 40.0);
  EXPECT_TRUE(s.env.passive_joints);
  EXPECT_EQ(s.env.episode_steps, 250);
  EXPECT_EQ(s.env.fall.control_steps, 80);
  EXPECT_EQ(s.env.fall.action_sigma, 0.0);
  EXPECT_TRUE(s.env.fall_transitions);  // env.py reset stores the fall's 80 steps
  EXPECT_EQ(s.env.min_strength, 0.4);
  EXPECT_EQ(s.hold_strength, 0.0);
  // Its Slower: π_slow at 800 Hz, the reference to one step past a head origin of 1.4 m, the
  // standing pose, COM 0.80326 m, k_d = k_p/5 and 150 steps standing.
  const SlowerConfig slower = base::ConfigReader::parse(Json::object(), "getup config", read_slower);
  EXPECT_EQ(slower.env.sim_hz, 800.0);
  EXPECT_EQ(slower.env.reference_end_m, 1.4);
  EXPECT_EQ(slower.env.reference_end_extra_steps, 1);
  EXPECT_EQ(slower.env.standing_com_m, 0.80326);
  EXPECT_EQ(slower.env.standing_kd_ratio, 5.0);
  EXPECT_EQ(slower.env.rise_kd_ratio, 10.0);
  EXPECT_EQ(slower.env.balance_steps, 150);
  EXPECT_TRUE(slower.env.seed_standing);
  EXPECT_EQ(slower.env.standing_pose, seed_standing_pose());
  EXPECT_EQ(s.eval_every, 20000);
  EXPECT_EQ(s.eval_starts, 10);
  EXPECT_EQ(s.curriculum.threshold, 60.0);
  EXPECT_EQ(s.curriculum.factor, 0.95);
  EXPECT_EQ(s.budget.min_steps, 300000);
  EXPECT_EQ(s.budget.max_steps, 800000);
  EXPECT_EQ(learner_spec(s)["algorithm"], "sac");
  EXPECT_EQ(learner_spec(s)["preset"], "paper");
}

TEST(GetupConfig, PpoIsAChoiceWithItsOwnFields) {
  const Settings s = read({{"algorithm", "ppo"}, {"ppo", {{"hidden", {32, 32}}, {"rollout_steps", 250}}}});
  const Json spec = learner_spec(s);
  EXPECT_EQ(spec["algorithm"], "ppo");
  EXPECT_EQ(spec["config"]["rollout_steps"], 250);
  EXPECT_EQ(error_path({{"algorithm", "td3"}}), "algorithm");
  EXPECT_EQ(error_path({{"ppo", {{"rollout_step", 250}}}}), "ppo");
}

// Slower's standing target is configurable joint by joint; unknown joints are refused at their path.
TEST(GetupConfig, TheStandingPoseIsSetPerJoint) {
  const SlowerConfig c = base::ConfigReader::parse(Json{{"standing_pose", {{"knee_left", -0.5}}}, {"standing_com_m", 0.9}},
                                                   "getup config", read_slower);
  for (const auto& [joint, angle] : c.env.standing_pose) {
    if (joint == "knee_left") {
      EXPECT_EQ(angle, -0.5);
    }
    if (joint == "knee_right") {
      EXPECT_EQ(angle, -0.39803);
    }
  }
  EXPECT_EQ(c.env.standing_com_m, 0.9);
  EXPECT_EQ(podium::testing::config_error_path({{"standing_pose", {{"knee", -0.5}}}}, read_slower), "standing_pose.knee");
  EXPECT_EQ(podium::testing::config_error_path({{"standing_pose", {{"knee_left", 7}}}}, read_slower), "standing_pose.knee_left");
}

// Table 1: π_slow learns with discount 0.95, π_weak with the preset's 0.97; the rest is shared.
TEST(GetupConfig, SlowerLearnsWithItsOwnDiscount) {
  const auto slower = [](const Json& config) { return base::ConfigReader::parse(config, "getup config", read_slower); };
  const Settings s = read({{"sac", {{"batch_size", 64}}}});
  const Json weak = learner_spec(s), slow = slower_learner_spec(s, slower(Json::object()));
  EXPECT_FALSE(weak["config"].contains("gamma"));  // the preset's
  EXPECT_EQ(slow["config"]["gamma"], 0.95);
  EXPECT_EQ(slow["config"]["batch_size"], 64);
  EXPECT_EQ(slower_learner_spec(s, slower({{"slow_gamma", 0.9}}))["config"]["gamma"], 0.9);
  EXPECT_EQ(learn::SacConfig::paper().gamma, 0.97);
  EXPECT_FALSE(slower_learner_spec(read({{"algorithm", "ppo"}}), slower(Json::object()))["config"].contains("gamma"));
  EXPECT_EQ(podium::testing::config_error_path({{"slow_gamma", 1.5}}, read_slower), "slow_gamma");
  EXPECT_EQ(podium::testing::config_error_path({{"slow_warm_start", "/nonexistent/training.ckpt"}}, read_slower),
            "slow_warm_start");
}

TEST(GetupConfig, BadValuesAreReportedAtTheirPath) {
  EXPECT_EQ(error_path({{"sac_preset", "papr"}}), "sac_preset");
  EXPECT_EQ(error_path({{"warm_start", "/nonexistent/training.ckpt"}}), "warm_start");
  EXPECT_EQ(error_path({{"hold_strength", 1.5}}), "hold_strength");
  EXPECT_EQ(error_path({{"control_hz", 33.0}}), "control_hz");
  EXPECT_EQ(error_path({{"eval_every", 300}}), "eval_every");  // not a multiple of 250
  EXPECT_EQ(error_path({{"total_steps", 30000}}), "total_steps");
  EXPECT_EQ(error_path({{"threads", 2}}), "threads");
  EXPECT_EQ(error_path({{"min_steps", 900000}}), "min_steps");
  EXPECT_EQ(error_path({{"strength_factor", 1.0}}), "strength_factor");
  EXPECT_EQ(error_path({{"sac", {{"hiden", {8}}}}}), "sac");
  EXPECT_EQ(error_path({{"sac", {{"log_interval_steps", 5}}}}), "sac");
  EXPECT_EQ(error_path({{"no_such_key", 1}}), "no_such_key");
  EXPECT_EQ(error_path({{"fall_transitions", 1}}), "fall_transitions");
  EXPECT_FALSE(read({{"fall_transitions", false}}).env.fall_transitions);
  EXPECT_EQ(error_path({{"copies", 2}, {"threads", 2}, {"eval_every", 20000}}), "(accepted)");
}

}  // namespace
}  // namespace podium::tasks::getup
