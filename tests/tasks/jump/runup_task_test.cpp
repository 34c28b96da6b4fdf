// The run-up stage through the real `podium` binary at the smoke preset: the task conformance
// suite on the stage, and campaigns/highjump.json's
// P-VAE and Stage 1 (cut to 2 samples), then one `runup` trial per Stage 1 trial (inputs "each"):
// the run-up imitating the authors' curved sprint to that trial's take-off, and the full jump
// (run-up, then the trial's jump policy) recorded as one motion. Skipped, with the reason, when
// ../shared/data/jump is absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <vector>

#include "finished_campaign.h"
#include "podium/base/json.h"
#include "podium/plugins/loader.h"
#include "process.h"
#include "shared_data.h"
#include "task_conformance.h"

namespace podium::tasks::jump {
namespace {

using base::Json;
namespace fs = std::filesystem;

// The stage in the task conformance suite (determinism, artifacts, cancel, resume from a kill),
// on the smoke preset toward a fixed target without a jump policy; no case without the reference
// run (../shared/data/jump).
std::vector<podium::testing::ConformanceCase> runup_conformance() {
  const fs::path data = podium::testing::shared_data("jump/data");  // the captured runs
  if (data.empty()) return {};
  return {{.task = "jump",
           .base_config = {{"stage", "runup"},
                           {"kind", "high_jump"},
                           {"runup_motion", (data / "motions/beyond/VC5_sprint__curves_03.txt").string()},
                           {"takeoff_features", {1.0, -1.0, 0.5, 1.0}}},
           .long_config = {{"total_samples", 100'000'000}},
           .resume_config = {{"total_samples", 1024}},
           .kill_after_metric_points = 24,
           .resumes_from_checkpoint = true,
           .artifacts = {"policy", "trajectory"},
           // Trained on from the smoke trial's checkpoint (256 samples, whose 22 metric points it sends
           // again first) to 1024; killed at its second test (34–44 points), after its first save.
           .warm_start = podium::testing::WarmStartCase{[](const fs::path& source, const Json&) {
                                                          return podium::testing::WarmStartCase::Order{
                                                              {{"runup_warm_start", (source / "training.ckpt").string()},
                                                               {"total_samples", 1024}}};
                                                        },
                                                        24}}};
}
using ::podium::testing::TaskConformance;
INSTANTIATE_TEST_SUITE_P(JumpRunupStage, TaskConformance, ::testing::ValuesIn(runup_conformance()));

TEST(JumpRunup, StageDeclaresItsMetricsAndNeedsAReferenceRun) {
  const auto task = plugins::load_task("jump");
  const Json d = task->describe({{"stage", "runup"}});
  EXPECT_TRUE(d["params"].empty());  // each trial's target is its input's take-off
  EXPECT_EQ(d["objectives"], Json({"task_reward", "full_jump_success_rate"}));
  std::set<std::string> metrics;
  for (const Json& m : d["metrics"]) metrics.insert(m["name"].get<std::string>());
  for (const char* m : {"runup/task_reward", "runup/omega_error_x", "runup/lateral_speed_error", "full_jump/success_rate"})
    EXPECT_TRUE(metrics.count(m)) << m;
}

TEST(JumpRunup, SmokeRunsExploreThenRunupAndTheFullJumpEndToEnd) {
  const fs::path data = podium::testing::shared_data("jump/data");  // the captured runs
  if (data.empty()) GTEST_SKIP() << "../shared/data/jump absent (PODIUM_SHARED_DIR): no reference run";
  Json spec = base::read_json_file(fs::path(PODIUM_SOURCE_DIR) / "campaigns/highjump.json");
  for (auto& stage : spec["stages"]) stage["preset"] = "smoke";
  spec["stages"][1]["budget"]["trials"] = 2;
  spec["stages"][2] = {{"name", "runup"},
                       {"task", "jump"},
                       {"preset", "smoke"},
                       {"config",
                        {{"stage", "runup"},
                         {"kind", "high_jump"},
                         {"runup_motion", (data / "motions/beyond/VC5_sprint__curves_03.txt").string()}}},
                       {"search", {{"algorithm", "random"}}},
                       {"budget", {{"trials", 2}}},
                       {"inputs", {{"stage", "explore"}, {"select", "all"}, {"per_trial", "each"}}}};
  spec["trial_timeout_s"] = 120;
  podium::testing::TempDir dir;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  ASSERT_EQ(campaign.trials.at("runup").size(), 2u);
  for (const auto& t : campaign.trials.at("runup")) {
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"policy", "trajectory"}));
    const auto metrics = campaign.metric_names(t);
    for (const char* m : {"runup/return", "runup/handover_rate", "runup/final_task_reward", "full_jump/success_rate"})
      EXPECT_TRUE(metrics.count(m)) << m;
    ASSERT_EQ(t.objectives.size(), 2u);
    EXPECT_GE(t.objectives[0], 0.0);
    EXPECT_LE(t.objectives[0], 1.0);
    EXPECT_EQ(t.result_info["omega_error"].size(), 3u);
    // The smoke preset hands over early in the run (runup_takeoff_time_s), so the jump runs too:
    // one motion, the run-up's frames and then the jump's, its time increasing throughout.
    std::string path;
    for (const auto& a : campaign.store->artifacts(t.id))
      if (a.name == "trajectory") path = a.path;
    std::ifstream in(fs::path(path).is_absolute() ? fs::path(path) : dir / path);
    std::string line;
    ASSERT_TRUE(std::getline(in, line)) << path;
    EXPECT_EQ(Json::parse(line)["format"], "podium-trajectory");
    EXPECT_FALSE(Json::parse(line)["props"].empty());  // the bar's suite
    double last = -1.0;
    int frames = 0;
    while (std::getline(in, line)) {
      const double time = Json::parse(line)["t"].get<double>();
      EXPECT_GT(time, last) << "frame " << frames;
      last = time, ++frames;
    }
    EXPECT_GT(frames, 10);
  }
}

}  // namespace
}  // namespace podium::tasks::jump
