// The sprint plugin through the real `podium` binary at the smoke preset: the task conformance
// suite on its stages (determinism, artifacts, cancel, resume from a kill), their descriptions,
// and campaigns/sprint.json end to end (start → accelerate → dip → race), each trial's landing
// states read back as stage 2's start set, the dip's CMA-ES run over the best stage-2 trial and the
// race stage's report read back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>

#include "finished_campaign.h"
#include "podium/base/json.h"
#include "podium/plugins/loader.h"
#include "process.h"
#include "sprint_env.h"
#include "sprint_preset.h"
#include "task_conformance.h"
#include "train_accelerate.h"

namespace podium::tasks::sprint {
namespace {

using base::Json;
namespace fs = std::filesystem;

// Each stage trained on from its smoke trial's checkpoint (256 samples, whose metric points it sends
// again first: 16 start, 26 accelerate) to 1024; killed at its second test, after its first save.
podium::testing::WarmStartCase::Order train_on_from(const fs::path& source, const Json&) {
  return {{{"warm_start", (source / "training.ckpt").string()}, {"total_samples", 1024}}};
}
PODIUM_TASK_CONFORMANCE(SprintStartStage, {.task = "sprint",
                                           .base_config = {{"stage", "start"}},
                                           .long_config = {{"total_samples", 100'000'000}},
                                           .resume_config = {{"total_samples", 1024}},
                                           .kill_after_metric_points = 24,
                                           .resumes_from_checkpoint = true,
                                           .artifacts = {"policy", "landings", "trajectory"},
                                           .warm_start = podium::testing::WarmStartCase{train_on_from, 28}});
// Without an input trial the accelerate stage runs from the fallback starts.
PODIUM_TASK_CONFORMANCE(SprintAccelerateStage, {.task = "sprint",
                                                .base_config = {{"stage", "accelerate"}},
                                                .long_config = {{"total_samples", 100'000'000}},
                                                .resume_config = {{"total_samples", 1024}},
                                                .kill_after_metric_points = 24,
                                                .resumes_from_checkpoint = true,
                                                .artifacts = {"policy", "dip_starts", "trajectory"},
                                                .warm_start = podium::testing::WarmStartCase{train_on_from, 45}});

// The dip: each trial gets a smoke accelerate trial whose snapshot set (dip_starts, or the
// stage's fallback when it is empty) is repeated to 200, so a trial of many dip episodes runs long
// enough to be cancelled or killed; it keeps no checkpoint (a candidate is seconds), so attempt 2
// runs it again to the same result.
Json dip_inputs(const fs::path& dir) {
  Json accelerate = podium::testing::smoke_input_trial("sprint", {{"stage", "accelerate"}}, dir, "accelerate");
  std::vector<Json> snapshots = load_handover_states(accelerate["artifacts"]["dip_starts"].get<std::string>());
  if (snapshots.empty()) {  // no smoke run gets there: the stage's own fallback, handover_before_line_m before the line
    const double smoke_hz =
        plugins::load_task("sprint")->describe({{"stage", "dip"}})["presets"]["smoke"]["sim_hz"].get<double>();
    snapshots = fallback_starts("smoke", smoke_hz,
                                load_sprint_preset("smoke").track.length_m - AccelerateSettings{}.handover_before_line_m);
  }
  std::vector<Json> many;
  for (std::size_t i = 0; many.size() < 200; ++i) many.push_back(snapshots[i % snapshots.size()]);
  const fs::path file = dir / "dip_starts_200.json";
  save_handover_states(file.string(), many);
  accelerate["artifacts"]["dip_starts"] = file.string();
  return Json::array({accelerate});
}
PODIUM_TASK_CONFORMANCE(SprintDipStage, {.task = "sprint",
                                         .base_config = {{"stage", "dip"}},
                                         .long_config = {{"dip_episodes", 200}},
                                         .resume_config = {{"dip_episodes", 60}},
                                         .kill_delay_s = 0.5,
                                         .artifacts = {"episodes"},
                                         .inputs = dip_inputs});

// The race: each trial gets a smoke start trial and a smoke accelerate trial (made for the test)
// and races their policies over the smoke preset's DR episodes; it keeps no checkpoint (a race is
// seconds), so attempt 2 runs it again to the same result.
Json race_inputs(const fs::path& dir) {
  return Json::array({podium::testing::smoke_input_trial("sprint", {{"stage", "start"}}, dir, "start"),
                      podium::testing::smoke_input_trial("sprint", {{"stage", "accelerate"}}, dir, "accelerate")});
}
PODIUM_TASK_CONFORMANCE(SprintRaceStage, {.task = "sprint",
                                          .base_config = {{"stage", "race"}},
                                          .long_config = {{"race_episodes", 1'000'000}},
                                          .resume_config = {{"race_episodes", 40}},
                                          .kill_delay_s = 0.5,
                                          .artifacts = {"race", "race_table", "trajectory"},
                                          .inputs = race_inputs});

TEST(SprintTask, TheStartStageDeclaresItsMetricsObjectivesAndPresets) {
  const auto task = plugins::load_task("sprint");
  const Json d = task->describe({{"stage", "start"}});
  EXPECT_TRUE(d["params"].empty());
  EXPECT_EQ(d["objectives"], Json({"landing_rate", "minus_tracking_error_rad"}));
  std::set<std::string> metrics;
  for (const Json& m : d["metrics"]) metrics.insert(m["name"].get<std::string>());
  for (const char* m : {"start/landing_rate", "start/tracking_error_rad", "start/com_speed_ratio", "start/final_landing_rate"})
    EXPECT_TRUE(metrics.count(m)) << m;
  for (const char* p : {"smoke", "quick", "paper"}) EXPECT_TRUE(d["presets"].contains(p)) << p;
  EXPECT_EQ(d["presets"]["quick"]["track"], "quick");
}

TEST(SprintTask, TheAccelerateStageDeclaresItsMetricsAndObjectives) {
  const auto task = plugins::load_task("sprint");
  const Json d = task->describe({{"stage", "accelerate"}});
  EXPECT_EQ(d["objectives"], Json({"finish_rate", "distance_m"}));
  std::set<std::string> metrics;
  for (const Json& m : d["metrics"]) metrics.insert(m["name"].get<std::string>());
  for (const char* m : {"accelerate/train_distance_m", "accelerate/finish_rate", "accelerate/first_speed_mps",
                        "accelerate/last_speed_mps", "accelerate/rise_distance_m", "accelerate/flight_rate"})
    EXPECT_TRUE(metrics.count(m)) << m;
}

TEST(SprintTask, TheDipStageDeclaresItsParamsFeaturesAndObjectives) {
  const auto task = plugins::load_task("sprint");
  const Json d = task->describe({{"stage", "dip"}});
  ASSERT_EQ(d["params"].size(), 2u);
  EXPECT_EQ(d["params"][0]["name"], "d_dip_m");
  EXPECT_EQ(d["params"][0]["low"], 1.0);
  EXPECT_EQ(d["params"][0]["high"], 5.0);
  EXPECT_EQ(d["params"][1]["name"], "theta_dip_deg");
  EXPECT_EQ(d["params"][1]["low"], 0.0);
  EXPECT_EQ(d["params"][1]["high"], 90.0);
  EXPECT_EQ(d["features"].size(), 2u);
  EXPECT_EQ(d["objectives"], Json({"minus_time_s", "finish_rate"}));
  EXPECT_EQ(d["presets"]["smoke"]["dip_episodes"], 4);
  EXPECT_EQ(d["presets"]["quick"]["dip_episodes"], 10);
  EXPECT_EQ(d["presets"]["paper"]["dip_episodes"], 32);
  EXPECT_EQ(d["config_defaults"]["dip_chest"], false);
}

std::string artifact_file(const podium::testing::FinishedCampaign& campaign, const fs::path& root, std::int64_t trial,
                          const std::string& name) {
  for (const auto& a : campaign.store->artifacts(trial))
    if (a.name == name) return (fs::path(a.path).is_absolute() ? fs::path(a.path) : root / a.path).string();
  return "";
}

TEST(SprintTask, TheRaceStageDeclaresItsObjectivesAndStrategyFeatures) {
  const auto task = plugins::load_task("sprint");
  const Json d = task->describe({{"stage", "race"}});
  EXPECT_EQ(d["objectives"], Json({"minus_mean_finish_time_s", "finish_rate"}));
  std::vector<std::string> features;
  for (const Json& f : d["features"]) features.push_back(f["name"].get<std::string>());
  EXPECT_EQ(features, (std::vector<std::string>{"step_length_m", "step_frequency_hz", "rise_distance_m"}));
  EXPECT_THROW(task->describe({{"stage", "race"}, {"race_seed", 20'240}}), base::ConfigError);  // eval_seed's
}

void expect_race_trial(const podium::testing::FinishedCampaign& campaign, const fs::path& root) {
  ASSERT_EQ(campaign.trials.at("race").size(), 1u);
  const auto& t = campaign.trials.at("race").front();
  EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"race", "race_table", "trajectory"}));
  ASSERT_EQ(t.objectives.size(), 2u);
  EXPECT_LT(t.objectives[0], 0.0);  // minus a mean time
  EXPECT_GE(t.objectives[1], 0.0);
  EXPECT_LE(t.objectives[1], 1.0);
  EXPECT_EQ(t.features.size(), 3u);
  // The report: the smoke preset's episodes, each with its draw, and the paired wind check.
  const Json report = base::read_json_file(artifact_file(campaign, root, t.id, "race"));
  ASSERT_EQ(report["episodes"].size(), 2u);
  EXPECT_EQ(report["headwind"].size(), 2u);
  EXPECT_EQ(report["tailwind"].size(), 2u);
  for (const Json& e : report["episodes"]) EXPECT_TRUE(e["draw"].contains("wind_mps") && e["draw"].contains("friction"));
  EXPECT_EQ(t.result_info["finish_rate"].get<double>(), t.objectives[1].get<double>());
  EXPECT_EQ(t.result_info["table"]["rows"].size(), 2u);
  EXPECT_TRUE(t.result_info.contains("summary"));
  std::ifstream text(artifact_file(campaign, root, t.id, "race_table"));
  const std::string table((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
  EXPECT_NE(table.find("Race over 10 m: 2 DR episodes"), std::string::npos) << table;
}

// The accelerate stage's reference runs made absolute (the campaign gives them relative to its
// file) and r_primitive switched on at the smoke preset (a short pretraining); without
// ../shared/data beside the checkout it stays off and `missing` says why.
void with_the_sport_primitive(Json& accelerate, std::string& missing) {
  const fs::path folder = fs::path(PODIUM_SOURCE_DIR) / "campaigns";
  Json& clips = accelerate["config"]["primitive_clips"];
  for (Json& c : clips) {
    const fs::path file = (folder / c["clip"].get<std::string>()).lexically_normal();
    if (!fs::is_regular_file(file)) missing = file.string() + " absent: r_primitive stays off";
    c["clip"] = file.string();
  }
  if (!missing.empty()) {
    accelerate["config"].erase("primitive_clips");
    return;
  }
  accelerate["config"]["primitive_weight"] = 1.0;
  accelerate["config"]["primitive_epochs"] = 20;
}

TEST(SprintTask, SmokeCampaignRunsStartAccelerateDipAndTheRaceEndToEnd) {
  Json spec = base::read_json_file(fs::path(PODIUM_SOURCE_DIR) / "campaigns/sprint.json");
  for (auto& stage : spec["stages"]) stage["preset"] = "smoke";
  ASSERT_EQ(spec["stages"][1]["name"], "accelerate");
  std::string missing;
  with_the_sport_primitive(spec["stages"][1], missing);
  if (!missing.empty()) std::printf("%s\n", missing.c_str());
  spec["trial_timeout_s"] = 120;
  ASSERT_EQ(spec["stages"][2]["name"], "dip");
  ASSERT_EQ(spec["stages"][2]["search"]["algorithm"], "cmaes");
  spec["stages"][2]["budget"]["trials"] = 12;  // two generations of λ = 6
  podium::testing::TempDir dir;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  ASSERT_EQ(campaign.trials.at("start").size(), 2u);
  std::size_t landings = 0;
  for (const auto& t : campaign.trials.at("start")) {
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"policy", "landings", "trajectory"}));
    const auto metrics = campaign.metric_names(t);
    for (const char* m : {"start/return", "start/landing_rate", "start/tracking_error_rad", "start/final_landing_rate"})
      EXPECT_TRUE(metrics.count(m)) << m;
    ASSERT_EQ(t.objectives.size(), 2u);
    EXPECT_GE(t.objectives[0], 0.0);
    EXPECT_LE(t.objectives[0], 1.0);
    EXPECT_LE(t.objectives[1], 0.0);
    // The landings: a set of hand-over states stage 2 reads (as many as the final landings).
    const std::vector<Json> states = load_handover_states(artifact_file(campaign, dir.path(), t.id, "landings"));
    EXPECT_EQ(static_cast<double>(states.size()), t.result_info["landings"].get<double>());
    for (const Json& s : states) EXPECT_TRUE(s.contains("draw") && s.contains("step_counter"));
    landings = std::max(landings, states.size());
    // Per reference: the four crouch starts, the final episodes split among them, the landings too.
    const Json& per = t.result_info["per_reference"];
    ASSERT_EQ(per.size(), 4u) << per;
    int episodes = 0, landed = 0;
    double lowest = 1.0;
    for (const auto& [name, r] : per.items()) {
      episodes += r["episodes"].get<int>(), landed += r["landings"].get<int>();
      if (r["episodes"].get<int>() > 0) lowest = std::min(lowest, r["landing_rate"].get<double>());
    }
    EXPECT_EQ(episodes, 4);  // the smoke preset's final_episodes
    EXPECT_EQ(static_cast<std::size_t>(landed), states.size());
    EXPECT_EQ(t.result_info["min_reference_landing_rate"].get<double>(), lowest);
    // How the final episodes ended: every one once, the landings among them.
    int ends = 0;
    for (const auto& [end, count] : t.result_info["ends"].items()) ends += count.get<int>();
    EXPECT_EQ(ends, 4) << t.result_info["ends"];
    EXPECT_EQ(t.result_info["ends"].value("landed", 0), landed) << t.result_info["ends"];
  }
  // Stage 2 from the best start trial's landings, or (none landed: the untrained smoke policy
  // rarely does) from the fallback, which its info says.
  ASSERT_EQ(campaign.trials.at("accelerate").size(), 2u);
  for (const auto& t : campaign.trials.at("accelerate")) {
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"policy", "dip_starts", "trajectory"}));
    const auto metrics = campaign.metric_names(t);
    for (const char* m : {"accelerate/train_distance_m", "accelerate/finish_rate", "accelerate/distance_m",
                          "accelerate/first_speed_mps", "accelerate/rise_distance_m", "accelerate/final_finish_rate"})
      EXPECT_TRUE(metrics.count(m)) << m;
    ASSERT_EQ(t.objectives.size(), 2u);
    EXPECT_GE(t.objectives[0], 0.0);
    EXPECT_LE(t.objectives[0], 1.0);
    const Json& starts = t.result_info["starts"];
    EXPECT_GE(starts["count"].get<int>(), 1);
    if (starts["fallback"].get<bool>()) {
      EXPECT_EQ(starts["count"], 4) << starts;  // the four crouch starts' last frames
    } else {
      EXPECT_NE(starts["source"].get<std::string>().find("landings of start/"), std::string::npos) << starts;
    }
    if (landings == 0) {
      EXPECT_TRUE(starts["fallback"].get<bool>()) << starts;
    }
    for (const char* k : {"train_distance_first_tenth_m", "train_distance_last_tenth_m", "rise_distance_m", "flight_rate"})
      EXPECT_TRUE(t.result_info.contains(k)) << k;
    // The sport primitive, pretrained on the runs: its strides, k and median KLs.
    const Json& primitive = t.result_info["primitive"];
    EXPECT_EQ(primitive.is_null(), !missing.empty()) << primitive;
    if (!primitive.is_null()) {
      EXPECT_GE(primitive["training_strides"].get<int>(), 10) << primitive;
      EXPECT_GT(primitive["k"].get<double>(), 0.0) << primitive;
    }
    // The dip stage's start set: hand-over states with their draws, one per run that got there.
    const std::vector<Json> dip = load_handover_states(artifact_file(campaign, dir.path(), t.id, "dip_starts"));
    EXPECT_EQ(static_cast<double>(dip.size()), t.result_info["handovers"].get<double>());
    for (const Json& s : dip) EXPECT_TRUE(s.contains("draw") && s.contains("world"));
  }
  // The dip: CMA-ES candidates in the box, each judged on the same snapshots with and without the
  // dip (the best accelerate trial's, or the fallback's when none got that far).
  const auto& dips = campaign.trials.at("dip");
  ASSERT_EQ(dips.size(), 12u);
  std::set<std::string> sources;
  for (const auto& t : dips) {
    const double d = t.params["d_dip_m"].get<double>(), theta = t.params["theta_dip_deg"].get<double>();
    EXPECT_GE(d, 1.0);
    EXPECT_LE(d, 5.0);
    EXPECT_GE(theta, 0.0);
    EXPECT_LE(theta, 90.0);
    EXPECT_EQ(t.features, (std::vector<double>{d, theta}));
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"episodes"}));
    const auto metrics = campaign.metric_names(t);
    EXPECT_TRUE(metrics.count("dip/time_s") && metrics.count("dip/no_dip_time_s"));
    const Json& info = t.result_info;
    ASSERT_EQ(t.objectives.size(), 2u);
    EXPECT_EQ(t.objectives[0].get<double>(), -info["dip"]["mean_time_s"].get<double>());
    EXPECT_EQ(info["gain_s"].get<double>(),
              info["no_dip"]["mean_time_s"].get<double>() - info["dip"]["mean_time_s"].get<double>());
    EXPECT_EQ(info["episodes"], 4);  // the smoke preset's dip_episodes
    EXPECT_EQ(info["table"]["rows"].size(), 4u);
    sources.insert(info["starts"]["source"].get<std::string>());
    // Per episode: the time from the snapshot, or the penalty for a fall.
    const Json episodes = base::read_json_file(artifact_file(campaign, dir.path(), t.id, "episodes"));
    ASSERT_EQ(episodes.size(), 4u);
    for (const Json& e : episodes)
      for (const char* which : {"no_dip", "dip"}) {
        const Json& x = e[which];
        if (x["finished"].get<bool>())
          EXPECT_EQ(x["time_s"].get<double>(), x["finish_time_s"].get<double>() - x["start_time_s"].get<double>());
        else EXPECT_EQ(x["time_s"], info["fall_penalty_s"]);
      }
    // Common random numbers: without the dip, every candidate's episodes are the same.
    EXPECT_EQ(info["no_dip"], dips.front().result_info["no_dip"]);
  }
  EXPECT_EQ(sources.size(), 1u);  // every candidate ran from the one hand-over
  // The second generation's candidates come from the updated distribution.
  EXPECT_EQ(dips.front().info["generation"], 0);
  EXPECT_EQ(dips.back().info["generation"], 1);
  // The race: the best start and accelerate trials' policies over the DR episodes, with the best
  // dip trial's (d_dip, θ_dip) and the dip check beside it.
  expect_race_trial(campaign, dir.path());
  const auto& race = campaign.trials.at("race").front();
  const std::string source = race.result_info["dip_source"].get<std::string>();
  EXPECT_TRUE(source.starts_with("dip trial dip/")) << source;
  const Json report = base::read_json_file(artifact_file(campaign, dir.path(), race.id, "race"));
  const Json& used = report["summary"]["dip"];
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& t : dips) best = std::max(best, t.objectives[0].get<double>());
  bool found = false;
  for (const auto& t : dips)
    if (t.params["d_dip_m"] == used["distance_m"] && t.params["theta_dip_deg"] == used["angle_deg"]) {
      found = true;
      EXPECT_EQ(t.objectives[0].get<double>(), best);
    }
  EXPECT_TRUE(found) << used;
  EXPECT_EQ(report["no_dip"].size(), 2u);
  EXPECT_EQ(report["summary"]["dip_check"]["episodes"], 2);
}

}  // namespace
}  // namespace podium::tasks::sprint
