// The jump plugin through the real `podium` binary: the task conformance suite (its resume case
// kills a smoke trial mid-run and checks the resumed attempt's result and metrics equal an
// uninterrupted run's), the stages' descriptions, and campaigns/highjump.json and obstaclejump.json
// at the smoke preset end to end (explore → novel, each novel trial handed one explore strategy's policy).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "campaign_spec.h"
#include "finished_campaign.h"
#include "podium/base/json.h"
#include "podium/plugins/loader.h"
#include "podium/store/store.h"
#include "process.h"
#include "task_conformance.h"

namespace podium::tasks::jump {
namespace {

using base::Json;
namespace fs = std::filesystem;

// The warm start: a novel trial (Stage 2) handed the explore smoke trial, its policy trained on.
podium::testing::WarmStartCase::Order novel_from(const fs::path& source, const Json& result) {
  const Json input = podium::testing::input_from_smoke(source, result);
  return {{{"stage", "novel"}, {"total_samples", 1024}}, Json::array({input})};
}
PODIUM_TASK_CONFORMANCE(Jump, {.task = "jump",
                               .long_config = {{"total_samples", 100'000'000}},
                               .resume_config = {{"total_samples", 1024}},
                               .kill_after_metric_points = 24,
                               .resumes_from_checkpoint = true,
                               .artifacts = {"policy", "trajectory"},
                               .warm_start = podium::testing::WarmStartCase{novel_from, 24}});

TEST(JumpTask, StagesDeclareTheTakeoffFeaturesAndTheirStrategyFeature) {
  const auto task = plugins::load_task("jump");
  const Json explore = task->describe({{"stage", "explore"}});
  ASSERT_EQ(explore["params"].size(), 4u);  // α, ω_x, ω_y, |v_y| (§3.6.1)
  EXPECT_EQ(explore["params"][0]["name"], "approach_angle");
  ASSERT_EQ(explore["features"].size(), 1u);  // the up-angle
  EXPECT_DOUBLE_EQ(explore["features"][0]["high"].get<double>(), M_PI);
  EXPECT_EQ(explore["objectives"][0], "z_reached_m");
  const Json novel = task->describe({{"stage", "novel"}, {"kind", "obstacle"}});
  EXPECT_EQ(novel["params"].size(), 3u);    // the root angular velocity
  EXPECT_EQ(novel["features"].size(), 3u);  // the bar-frame rotation
  try {
    task->describe({{"stage", "stage2"}});
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("stage: \"stage2\" is not one of pose_vae, explore, novel"), std::string::npos)
        << e.what();
  }
}

TEST(JumpTask, TakeoffBoxNarrowsTheSearchedRanges) {
  const auto task = plugins::load_task("jump");
  const Json d = task->describe({{"stage", "explore"}, {"takeoff_box", {{"root_omega_x", {-1.0, 2.0}}}}});
  EXPECT_EQ(d["params"][1]["name"], "root_omega_x");
  EXPECT_EQ(d["params"][1]["low"], -1.0);
  EXPECT_EQ(d["params"][1]["high"], 2.0);
  EXPECT_EQ(d["params"][0]["low"], -0.5);  // the others keep takeoff.h's defaults
  for (const Json& bad : {Json{{"root_omega_x", {2.0, 1.0}}}, Json{{"root_omega_x", {1.0}}}, Json{{"omega", {0.0, 1.0}}},
                          Json{{"root_omega_z", {0.0, 1.0}}}}) {  // ω_z: an obstacle feature
    try {
      task->describe({{"stage", "explore"}, {"takeoff_box", bad}});
      ADD_FAILURE() << bad.dump();
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find("takeoff_box"), std::string::npos) << e.what();
    }
  }
}

TEST(JumpTask, ABadConfigIsRejectedAtSubmitAtItsJsonPath) {
  Json spec = base::read_json_file(fs::path(PODIUM_SOURCE_DIR) / "campaigns/highjump.json");
  spec["stages"][1]["config"]["copies"] = 0;
  podium::testing::TempDir dir;
  podium::testing::write_file(dir / "spec.json", spec.dump());
  const auto run = podium::testing::run_podium({"submit", (dir / "spec.json").string()}, dir.path());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("stages[1].config.copies: 0 is not"), std::string::npos) << run.err;
}

// The captured techniques' folder, relative to the spec's folder, reaches the workers absolute
// (the trials run in their own folders); a file or a missing folder is refused at submit.
TEST(JumpTask, TheCapturedTechniquesFolderIsResolvedAgainstTheSpecAtSubmit) {
  podium::testing::TempDir dir;
  fs::create_directories(dir / "specs" / "captures");
  podium::testing::write_file(dir / "specs" / "captures" / "note.txt", "not a folder\n");
  Json spec = base::read_json_file(fs::path(PODIUM_SOURCE_DIR) / "campaigns/highjump.json");
  spec["stages"][1]["config"]["captured_motions"] = "captures";
  podium::testing::write_file(dir / "specs" / "spec.json", spec.dump());
  const auto ok = podium::testing::run_podium({"submit", "specs/spec.json"}, dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  EXPECT_EQ(store->stages(1).at(1).task_config["captured_motions"], (dir / "specs" / "captures").string());
  for (const char* bad : {"captures/note.txt", "nowhere"}) {
    spec["stages"][1]["config"]["captured_motions"] = bad;
    podium::testing::write_file(dir / "specs" / "spec.json", spec.dump());
    const auto refused = podium::testing::run_podium({"submit", "specs/spec.json"}, dir.path());
    EXPECT_EQ(refused.exit_code, 2) << bad;
    EXPECT_NE(refused.err.find("stages[1].config.captured_motions: "), std::string::npos) << refused.err;
  }
}

// A shipped jump campaign (pose_vae → explore → novel) at the smoke preset, cut to
// `explore_samples` Stage 1 samples and one novel trial for each of the two best of them. At smoke
// no jump is learnt, so no explore trial clears its bar (the jump's success rule) or is a strategy,
// and the shipped "best_per_strategy" would hand over nothing: that stage fails and says why
// (tests/orchestrator/hand_over_test.cpp). Stage 2's mechanics run from the top 2 instead.
Json smoke_campaign(const std::string& file, int explore_samples) {
  Json spec = base::read_json_file(fs::path(PODIUM_SOURCE_DIR) / "campaigns" / file);
  for (auto& stage : spec["stages"]) stage["preset"] = "smoke";
  spec["stages"][1]["budget"]["trials"] = explore_samples;
  spec["stages"][2]["search"]["config"]["trials_per_input"] = 1;
  spec["stages"][2]["budget"]["trials"]["per_input"] = 1;
  spec["stages"][2]["inputs"]["select"] = "top";
  spec["stages"][2]["inputs"]["k"] = 2;
  spec["trial_timeout_s"] = 120;
  return spec;
}

// campaigns/highjump.json at the smoke preset through the real CLI, cut to 4 explore samples and
// one novel trial for each of the two best: the P-VAE, Stage 1 acting through it, Stage 2 through the same one.
TEST(JumpCampaign, SmokeRunsExploreThenNovelEndToEnd) {
  const Json spec = smoke_campaign("highjump.json", 4);
  podium::testing::TempDir dir;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  const auto& trials = campaign.trials;
  ASSERT_EQ(trials.size(), 3u);
  ASSERT_EQ(trials.at("pose_vae").size(), 1u);
  EXPECT_EQ(campaign.artifact_names(trials.at("pose_vae")[0]), (std::set<std::string>{"pose_vae"}));
  ASSERT_EQ(trials.at("explore").size(), 4u);
  for (const auto& t : trials.at("explore")) {
    ASSERT_EQ(t.features.size(), 1u);
    EXPECT_TRUE(t.features[0] >= 0.0 && t.features[0] <= M_PI) << t.features[0];
    EXPECT_EQ(t.result_info["bar_frame_rotation"].size(), 3u);
    const double alpha = t.params["approach_angle"].get<double>();  // inside the spec's takeoff_box
    EXPECT_TRUE(alpha >= 0.4 && alpha <= 2.1) << alpha;
    EXPECT_EQ(campaign.artifact_names(t),
              (std::set<std::string>{"policy", "trajectory", "pose_vae"}));  // the P-VAE handed on to Stage 2
    EXPECT_TRUE(t.result_info["summary"].contains("bar reached m")) << t.result_info.dump();
    const auto metrics = campaign.metric_names(t);
    for (const char* m : {"curriculum/z_m", "curriculum/control_hz", "train/avg_reward", "eval/success_rate_start_bar"})
      EXPECT_TRUE(metrics.count(m)) << m;
  }
  // A strategy only where the jump cleared its bar.
  for (const auto& t : trials.at("explore"))
    EXPECT_EQ(t.strategy.has_value(), t.result_info["start_bar"]["deterministic_success"].get<bool>());
  // One novel trial per handed-over explore trial, each at its input's take-off state.
  ASSERT_EQ(trials.at("novel").size(), 2u);
  std::set<Json> explore_params, novel_params;
  for (const auto& t : trials.at("explore")) explore_params.insert(t.params);
  for (const auto& t : trials.at("novel")) {
    EXPECT_EQ(t.features.size(), 3u);
    EXPECT_TRUE(explore_params.count(t.params)) << t.params;
    novel_params.insert(t.params);
  }
  EXPECT_EQ(novel_params.size(), 2u);

  // The demo's path: an explore trial's policy, P-VAE and take-off jumped again by the evaluate
  // stage, without training (the trial names it and records the motion).
  const store::TrialRecord& first = trials.at("explore").front();
  std::map<std::string, std::string> files;
  for (const auto& a : campaign.store->artifacts(first.id)) files[a.name] = a.path;
  std::vector<double> takeoff;
  for (const char* name : {"approach_angle", "root_omega_x", "root_omega_y", "lateral_speed"})
    takeoff.push_back(first.params[name].get<double>());
  const Json shipped = {
      {"name", "shipped"},
      {"seed", 3},
      {"workers", 1},
      {"retries", 0},
      {"trial_timeout_s", 120},
      {"stages",
       {{{"name", "jumps"},
         {"task", "jump"},
         {"preset", "smoke"},
         {"config",
          {{"stage", "evaluate"},
           {"kind", "high_jump"},
           {"shipped", {{{"policy", files["policy"]}, {"pose_vae", files["pose_vae"]}, {"takeoff", takeoff}}}}}},
         {"search", {{"algorithm", "random"}}},
         {"budget", {{"trials", 1}}}}}}};
  const std::int64_t replayed = std::stoll(podium::testing::submit_spec(dir.path(), shipped));
  ASSERT_EQ(podium::testing::run_podium({"run"}, dir.path()).exit_code, 0);
  const auto again = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  const auto jumps = again->trials(again->stages(replayed).at(0).id);
  ASSERT_EQ(jumps.size(), 1u);
  ASSERT_EQ(jumps[0].state, "done") << jumps[0].error;
  ASSERT_EQ(jumps[0].features.size(), 1u);
  EXPECT_NEAR(jumps[0].features[0], first.features[0], 1e-9);  // the same deterministic jump as the trial's own evaluation
  EXPECT_EQ(again->artifacts(jumps[0].id).at(0).name, "trajectory");
}

// campaigns/obstaclejump.json at the smoke preset, cut to 3 explore samples and one novel trial
// for each of the two best: the box's 3-D take-off (root angular velocity) and the same two stages.
TEST(JumpCampaign, ObstacleSmokeRunsExploreThenNovelEndToEnd) {
  const Json spec = smoke_campaign("obstaclejump.json", 3);
  podium::testing::TempDir dir;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  const auto& trials = campaign.trials;
  ASSERT_EQ(trials.at("explore").size(), 3u);
  for (const auto& t : trials.at("explore")) {
    EXPECT_EQ(t.params.size(), 3u) << t.params;  // ω_x, ω_y, ω_z
    ASSERT_EQ(t.features.size(), 1u);
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"policy", "trajectory", "pose_vae"}));
    EXPECT_TRUE(campaign.metric_names(t).count("curriculum/z_m"));
  }
  ASSERT_EQ(trials.at("novel").size(), 2u);
  for (const auto& t : trials.at("novel")) EXPECT_EQ(t.features.size(), 3u);
}

}  // namespace
}  // namespace podium::tasks::jump
