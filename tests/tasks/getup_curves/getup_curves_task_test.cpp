// The getup_curves plugin through the real `podium` binary: the task
// conformance suite (its resume case kills a smoke trial mid-run and checks the
// resumed attempt's result and metrics equal an uninterrupted run's), bad
// configs named at their JSON path, and campaigns/getup_curves.json at the
// smoke preset end to end.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <string>

#include "curve_edit.h"
#include "curve_extraction.h"
#include "edit_stage.h"
#include "finished_campaign.h"
#include "podium/base/json.h"
#include "podium/learn/vae.h"
#include "podium/plugins/loader.h"
#include "podium/sim/model.h"
#include "process.h"
#include "shared_data.h"
#include "task_conformance.h"

namespace podium::tasks::getup_curves {
namespace {

using base::Json;
namespace fs = std::filesystem;

// Warm-started from the smoke trial's checkpoint (256 steps, whose 18 metric points it sends again
// first) to 1024; killed at its second test (28–36 points), after its first save.
podium::testing::WarmStartCase::Order train_on_from(const fs::path& source, const Json&) {
  return {{{"warm_start", (source / "training.ckpt").string()}, {"total_steps", 1024}}};
}
PODIUM_TASK_CONFORMANCE(GetupCurves, {.task = "getup_curves",
                                      .long_config = {{"total_steps", 100'000'000}},
                                      .resume_config = {{"total_steps", 1024}},
                                      .kill_after_metric_points = 20,
                                      .resumes_from_checkpoint = true,
                                      .artifacts = {"policy", "trajectory", "curves"},
                                      .warm_start = podium::testing::WarmStartCase{train_on_from, 30}});

// campaigns/getup_curves.json with its pose clips' paths made absolute (the file gives them
// relative to itself, and the tests write specs elsewhere). Without ../shared/data beside the
// checkout the pose_cvae stage is dropped and the train stage acts on PD targets; `missing` says
// why (empty when the clips are there).
Json campaign_spec(std::string& missing) {
  const fs::path folder = fs::path(PODIUM_SOURCE_DIR) / "campaigns";
  Json spec = base::read_json_file(folder / "getup_curves.json");
  Json& cvae = spec["stages"][0];
  bool present = true;
  for (Json& clip : cvae["config"]["pose_clips"])
    for (const char* key : {"clip", "character"}) {
      const fs::path file = (folder / clip[key].get<std::string>()).lexically_normal();
      present = present && fs::is_regular_file(file);
      clip[key] = file.string();
    }
  if (present) return spec;
  missing = "../shared/data absent: the train stage acts on PD targets, without the pose_cvae stage";
  spec["stages"].erase(0);
  spec["stages"][0].erase("inputs");
  spec["stages"][0]["config"]["actions"] = "targets";
  return spec;
}
Json campaign_spec() {
  std::string missing;
  Json spec = campaign_spec(missing);
  if (!missing.empty()) std::printf("%s\n", missing.c_str());
  return spec;
}
// The campaign's stage of that name.
Json& stage_named(Json& spec, const std::string& name) {
  for (Json& stage : spec["stages"])
    if (stage["name"] == name) return stage;
  throw std::runtime_error("campaigns/getup_curves.json has no stage " + name);
}
// The train stage alone, on PD targets (the tests of the curriculum need no C-VAE).
Json train_alone() {
  Json spec = campaign_spec();
  Json train = stage_named(spec, "train");
  train.erase("inputs");
  train["config"]["actions"] = "targets";
  spec["stages"] = Json::array({train});
  return spec;
}

TEST(GetupCurvesTask, DescribesItsObjectivesAndShippedCurves) {
  const auto task = plugins::load_task("getup_curves");
  const Json d = task->describe(Json::object());
  EXPECT_EQ(d["objectives"], Json({"success_rate", "mean_r_task"}));
  EXPECT_TRUE(d["features"].empty());
  EXPECT_EQ(d["config_defaults"]["curves"], Json({"faceup", "facedown"}));
  // The paper preset carries §5.6's settings.
  const Json paper = d["presets"]["paper"];
  EXPECT_EQ(paper["ppo"]["hidden"], Json({256, 256}));
  EXPECT_EQ(paper["ppo"]["minibatch_size"], 256);
  EXPECT_DOUBLE_EQ(paper["ppo"]["policy_lr_start"].get<double>(), 1e-4);
  EXPECT_DOUBLE_EQ(paper["ppo"]["sigma_end"].get<double>(), 0.3);
  EXPECT_EQ(paper["copies"], 16);
}

// One line naming the JSON path and the value.
std::string describe_error(const Json& config) {
  try {
    plugins::load_task("getup_curves")->describe(config);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(GetupCurvesTask, ABadConfigIsNamedAtItsPathWithItsValue) {
  std::string e = describe_error({{"curves", {"faceup", "no_such_curve"}}});
  EXPECT_NE(e.find("curves[1]: \"no_such_curve\" is not a curve file"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // A curve file with a bad entry: both files and both paths on one line.
  podium::testing::TempDir dir;
  Json curve = base::read_json_file(fs::path(PODIUM_SOURCE_DIR) / "tasks/getup_curves/data/curves/faceup.json");
  curve["duration_s"] = -1.0;
  podium::testing::write_file(dir / "bad.json", curve.dump());
  e = describe_error({{"curves", {(dir / "bad.json").string()}}});
  EXPECT_NE(e.find("curves[0]: "), std::string::npos) << e;
  EXPECT_NE(e.find("bad.json: duration_s: -1.0 is not"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  e = describe_error({{"sim_hz", 100.0}});
  EXPECT_NE(e.find("sim_hz"), std::string::npos) << e;
  EXPECT_NE(e.find("100"), std::string::npos) << e;
  e = describe_error({{"ppo", {{"hidden", "wide"}}}});
  EXPECT_NE(e.find("ppo"), std::string::npos) << e;
  e = describe_error({{"stage", "pose"}});
  EXPECT_NE(e.find("stage: \"pose\" is not one of"), std::string::npos) << e;
}

TEST(GetupCurvesTask, ABadCampaignConfigIsRejectedAtSubmitWithTheFileAndPath) {
  Json spec = campaign_spec();
  stage_named(spec, "train")["config"]["copies"] = 0;
  podium::testing::TempDir dir;
  podium::testing::write_file(dir / "spec.json", spec.dump());
  const auto run = podium::testing::run_podium({"submit", (dir / "spec.json").string()}, dir.path());
  EXPECT_EQ(run.exit_code, 2);
  const std::string path = "stages[" + std::to_string(spec["stages"].size() - 2) + "].config.copies: 0 is not";
  EXPECT_NE(run.err.find(path), std::string::npos) << run.err;
}

// The edit stage's edits of a shipped curve: the rise moved to a fraction of T (to the fit's
// round-off), one control point of h moved exactly, T scaled with the points kept; the name says
// it is an edit.
TEST(GetupCurvesEdit, MovesTheRiseAPointOfHAndScalesT) {
  const StyleCurve base = load_style_curve(shipped_curve_dir() / "faceup.json");
  const StyleCurve point = edited_curve(base, {0.0, 0.1, 1.0}, 5);
  EXPECT_EQ(point.name, "faceup+edit");
  for (int j = 0; j < kControlPoints; ++j) {
    EXPECT_EQ(point.points(0, j), base.points(0, j) + (j == 5 ? 0.1 : 0.0)) << j;
    EXPECT_EQ(point.points.col(j).tail<2>(), base.points.col(j).tail<2>()) << j;
  }
  const StyleCurve slower = edited_curve(base, {0.0, 0.0, 1.2}, 5);
  EXPECT_DOUBLE_EQ(slower.duration_s, 1.2 * base.duration_s);
  EXPECT_EQ(slower.points, base.points);
  // shift_rise refits the 7 inner control points: the larger the move, the farther the fit lands
  // from the asked rise (faceup's own rise is at 0.76 of T).
  for (const double fraction : {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9}) {
    const StyleCurve moved = edited_curve(base, {fraction, 0.0, 1.5}, 5);
    const double at = rise_time_s(moved) / moved.duration_s;
    std::printf("rise asked at %.2f of T, fitted at %.3f\n", fraction, at);
    EXPECT_NEAR(at, fraction, 0.04) << fraction;
  }
}

// campaigns/getup_curves.json at the smoke preset through the real CLI: two
// trained trials, each with its policy, a recorded motion per shipped curve and
// their target-vs-achieved features.
// The edit stage: each trial the best train trial's policy on its edit of faceup — the edited
// curve written (its T the base's × duration_scale), 27 knot features, its episode recorded with
// its target and achieved features, the final test's figures.
void expect_edit_trials(const podium::testing::FinishedCampaign& campaign, const fs::path& dir) {
  const StyleCurve base = load_style_curve(shipped_curve_dir() / "faceup.json");
  ASSERT_EQ(campaign.trials.at("edit").size(), 6u);
  for (const auto& t : campaign.trials.at("edit")) {
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"edited_curve", "curves", "trajectory"}));
    EXPECT_EQ(t.features.size(), 27u);
    std::string file;
    for (const auto& a : campaign.store->artifacts(t.id))
      if (a.name == "edited_curve") file = a.path;
    const StyleCurve edited = load_style_curve(fs::path(file).is_absolute() ? fs::path(file) : dir / file);
    EXPECT_NEAR(edited.duration_s, base.duration_s * t.params["duration_scale"].get<double>(), 1e-9);
    const CurveEdit edit{t.params["rise_fraction"].get<double>(), t.params["h_offset_m"].get<double>(),
                         t.params["duration_scale"].get<double>()};
    EXPECT_TRUE(edited.points.isApprox(edited_curve(base, edit, 5).points, 1e-9));  // the file holds degrees
    EXPECT_EQ(t.objectives[0], t.result_info["success_rate"]);
    EXPECT_TRUE(t.result_info.contains("rise_time_s") && t.result_info.contains("h_error_m"));
  }
}

TEST(GetupCurvesCampaign, SmokeTrainsEndToEnd) {
  std::string missing;
  Json spec = campaign_spec(missing);
  if (!missing.empty()) std::printf("%s\n", missing.c_str());
  for (auto& stage : spec["stages"]) stage["preset"] = "smoke";
  stage_named(spec, "train")["budget"]["trials"] = 2;
  stage_named(spec, "edit")["budget"]["trials"] = 6;
  spec["trial_timeout_s"] = 120;
  podium::testing::TempDir dir;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  ASSERT_EQ(campaign.trials.at("train").size(), 2u);
  expect_edit_trials(campaign, dir.path());
  std::set<std::string> artifacts = {"policy", "trajectory", "trajectory_1", "curves"};
  if (missing.empty()) artifacts.insert("pose_cvae");  // acting through the pose_cvae trial's C-VAE
  for (const auto& t : campaign.trials.at("train")) {
    EXPECT_EQ(campaign.artifact_names(t), artifacts);
    const auto metrics = campaign.metric_names(t);
    for (const char* m : {"test/return", "test/success_rate", "test/mean_r_task", "test/average_return_rate", "test/episode_s",
                          "final/success_rate"})
      EXPECT_TRUE(metrics.count(m)) << m;
    ASSERT_EQ(t.objectives.size(), 2u);
    EXPECT_GE(t.objectives[0], 0.0);
    EXPECT_LE(t.objectives[0], 1.0);
    EXPECT_GT(t.objectives[1], 0.0);  // r_task > 0 at every step an episode runs
    EXPECT_LE(t.objectives[1], 1.0);
    EXPECT_EQ(t.result_info["recorded_curves"], Json({"faceup", "facedown"}));
    EXPECT_EQ(t.result_info["table"]["rows"].size(), 2u);
    // How each curve's test episodes followed it: its success, the tracking errors of the
    // successful ones (none without one), its rise.
    const Json& following = t.result_info["following"];
    ASSERT_EQ(following.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const Json& f = following[k];
      EXPECT_EQ(f["curve"], t.result_info["recorded_curves"][k]);
      EXPECT_EQ(f["success_rate"], t.result_info["curve_success"][k]);
      EXPECT_EQ(f["h_error_m"].is_null(), f["successes"].get<int>() == 0) << f;
      EXPECT_EQ(f["rise_time_s"].is_null(), f["risen"].get<int>() == 0) << f;
      if (!f["rise_time_s"].is_null()) {
        EXPECT_GE(f["rise_time_s"].get<double>(), 0.0);
      }
    }
    std::string curves;
    for (const auto& a : campaign.store->artifacts(t.id))
      if (a.name == "curves") curves = a.path;
    const Json series = base::read_json_file(fs::path(curves).is_absolute() ? fs::path(curves) : dir / curves);
    ASSERT_EQ(series["episodes"].size(), 2u);
    for (const Json& e : series["episodes"]) {
      const std::size_t n = e["t_s"].size();
      EXPECT_GT(n, 1u);
      for (const char* block : {"target", "achieved"})
        for (const char* f : {"h_m", "theta_x_deg", "theta_z_deg"}) EXPECT_EQ(e[block][f].size(), n) << block << " " << f;
    }
    // The curves start lying as their names say: faceup on the back (θ_z near
    // 0), facedown on the front.
    EXPECT_LT(series["episodes"][0]["target"]["theta_z_deg"][0].get<double>(), 30.0);
    EXPECT_GT(series["episodes"][1]["target"]["theta_z_deg"][0].get<double>(), 150.0);
    // The smoke preset tests one start per curve, the recorded one: its figures are the recorded
    // series' (the errors over t ≤ T when it succeeded, the first instant h reaches half the
    // standing neck height).
    const double rise_height = 0.5 * standing_neck_height(*sim::load_shipped_model("humanoid34"));
    for (std::size_t k = 0; k < 2; ++k) {
      const Json& e = series["episodes"][k];
      const Json& f = t.result_info["following"][k];
      EXPECT_EQ(f["successes"].get<int>(), e["success"].get<bool>() ? 1 : 0);
      double h = 0.0, angle = 0.0;
      int steps = 0;
      std::optional<double> rise;
      for (std::size_t i = 0; i < e["t_s"].size(); ++i) {
        const double at = e["t_s"][i].get<double>(), achieved = e["achieved"]["h_m"][i].get<double>();
        if (!rise && achieved >= rise_height) rise = at;
        if (at > e["curve"]["duration_s"].get<double>() + 1e-9) continue;
        h += std::abs(achieved - e["target"]["h_m"][i].get<double>()), ++steps;
        for (const char* a : {"theta_x_deg", "theta_z_deg"})
          angle += 0.5 * std::abs(e["achieved"][a][i].get<double>() - e["target"][a][i].get<double>());
      }
      EXPECT_EQ(f["rise_time_s"].is_null(), !rise.has_value());
      if (rise) {
        EXPECT_NEAR(f["rise_time_s"].get<double>(), *rise, 1e-9);
      }
      if (e["success"].get<bool>()) {
        EXPECT_NEAR(f["h_error_m"].get<double>(), h / steps, 1e-9);
        EXPECT_NEAR(f["angle_error_deg"].get<double>(), angle / steps, 1e-6);
      }
    }
  }
}

// The edit stage without an input trial runs a shipped policy (the demo's authoring stage): here
// a smoke train trial's policy and its C-VAE as files.
TEST(GetupCurvesCampaign, TheEditStageRunsAShippedPolicy) {
  std::string missing;
  Json spec = campaign_spec(missing);
  for (auto& stage : spec["stages"]) stage["preset"] = "smoke";
  stage_named(spec, "train")["budget"]["trials"] = 1;
  stage_named(spec, "edit")["budget"]["trials"] = 2;
  stage_named(spec, "edit")["search"] = {{"algorithm", "random"}};
  spec["trial_timeout_s"] = 120;
  podium::testing::TempDir dir;
  const auto trained = podium::testing::run_campaign_to_end(dir.path(), spec);
  const auto& train = trained.trials.at("train").at(0);
  Json edit = stage_named(spec, "edit");
  edit.erase("inputs");
  for (const auto& a : trained.store->artifacts(train.id)) {
    const fs::path file = fs::path(a.path).is_absolute() ? fs::path(a.path) : dir / a.path;
    if (a.name == "policy") edit["config"]["edit_shipped_policy"] = file.string();
    if (a.name == "pose_cvae") edit["config"]["edit_shipped_cvae"] = file.string();
  }
  EXPECT_EQ(edit["config"].contains("edit_shipped_cvae"), missing.empty());
  Json shipped = spec;
  shipped["name"] = "shipped";
  shipped["stages"] = Json::array({edit});
  podium::testing::TempDir again;
  const auto run = podium::testing::run_campaign_to_end(again.path(), shipped);
  ASSERT_EQ(run.trials.at("edit").size(), 2u);
  for (const auto& t : run.trials.at("edit")) {  // done: the policy's observation and action fitted the env
    EXPECT_EQ(t.features.size(), 27u);
    EXPECT_EQ(t.result_info["policy"], edit["config"]["edit_shipped_policy"]);
    EXPECT_EQ(run.artifact_names(t), (std::set<std::string>{"edited_curve", "curves", "trajectory"}));
  }
}

// §5.4 end to end: a curve a limp character follows by lying still (h 5 cm: every episode a
// success, with early termination off) and one success to unlock: the easy region opens to
// training during the smoke run (curriculum/open_levels), the tests then report it, and the
// trial says how many regions were open at the end.
TEST(GetupCurvesCampaign, TheTerrainCurriculumOpensTheNextRegionAfterItsSuccesses) {
  podium::testing::TempDir dir;
  const fs::path lie = dir / "lie.json";
  base::write_json_file_atomic(lie, {{"name", "lie"},
                                     {"duration_s", 0.5},
                                     {"start", {{"drop", "supine"}}},
                                     {"source", "test: lying still"},
                                     {"control_points",
                                      {{"h_m", std::vector<double>(9, 0.05)},
                                       {"theta_x_deg", std::vector<double>(9, 90.0)},
                                       {"theta_z_deg", std::vector<double>(9, 0.0)}}}});
  Json spec = train_alone();
  Json train = spec["stages"][0];
  train["preset"] = "smoke";
  train["budget"]["trials"] = 1;
  train["config"]["curves"] = {lie.string()};
  train["config"]["early_termination"] = false;
  train["config"]["terrain_successes_to_unlock"] = 1;
  train["config"]["record_curves"] = 1;
  spec["stages"] = Json::array({train});
  spec["trial_timeout_s"] = 120;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  const auto& t = campaign.trials.at("train").at(0);
  const auto metrics = campaign.metric_names(t);
  EXPECT_TRUE(metrics.count("curriculum/open_levels"));
  EXPECT_TRUE(metrics.count("test/success_rate/flat"));
  EXPECT_TRUE(metrics.count("test/success_rate/easy"));
  EXPECT_EQ(t.result_info["open_levels"], 2);
}

// §6.4's "no terrain curriculum" ablation: the step count opens the regions (here every 64
// control steps: the smoke run's second iteration opens easy), whatever the successes.
TEST(GetupCurvesCampaign, AFixedScheduleOpensTheRegionsByStepCount) {
  Json spec = train_alone();
  Json train = spec["stages"][0];
  train["preset"] = "smoke";
  train["budget"]["trials"] = 1;
  train["config"]["terrain_schedule_steps"] = 64;
  train["config"]["record_curves"] = 1;
  spec["stages"] = Json::array({train});
  spec["trial_timeout_s"] = 120;
  podium::testing::TempDir dir;
  const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
  const auto& t = campaign.trials.at("train").at(0);
  EXPECT_TRUE(campaign.metric_names(t).count("curriculum/open_levels"));
  EXPECT_EQ(t.result_info["open_levels"], 2);
}

// DeepMimic's two get-up clips on their skeleton as pose_clips, or empty (with the reason) when
// ../shared/data is absent.
Json deepmimic_getup_clips(std::string& missing) {
  const fs::path data = podium::testing::shared_data("deepmimic/data");
  if (data.empty() || !fs::exists(data / "characters/humanoid3d.txt")) {
    missing = "../shared/data/deepmimic absent (PODIUM_SHARED_DIR): no clips for the C-VAE";
    return Json::array();
  }
  Json clips = Json::array();
  for (const char* way : {"faceup", "facedown"})
    clips.push_back({{"clip", (data / ("motions/humanoid3d_getup_" + std::string(way) + ".txt")).string()},
                     {"character", (data / "characters/humanoid3d.txt").string()}});
  return clips;
}

// §6.4's ablation at the smoke preset: a pose_cvae trial on DeepMimic's get-up clips without
// their labels (cvae_conditional false) makes an unconditional pose VAE, through which the
// campaign's train stage acts (the conditional C-VAE is the campaign's own path, checked by
// SmokeTrainsEndToEnd); the saved VAE has no condition.
TEST(GetupCurvesCampaign, SmokeTrainsThroughAPoseCvaeTrial) {
  std::string missing;
  const Json clips = deepmimic_getup_clips(missing);
  if (!missing.empty()) GTEST_SKIP() << missing;
  {
    const bool conditional = false;
    Json spec = campaign_spec();
    Json train = stage_named(spec, "train");
    train["preset"] = "smoke";
    train["config"]["actions"] = "cvae";
    train["budget"]["trials"] = 1;
    train["inputs"] = {{"stage", "pose_cvae"}, {"select", "all"}, {"per_trial", "each"}};
    spec["stages"] = Json::array({{{"name", "pose_cvae"},
                                   {"task", "getup_curves"},
                                   {"preset", "smoke"},
                                   {"config", {{"stage", "pose_cvae"}, {"pose_clips", clips}, {"cvae_conditional", conditional}}},
                                   {"search", {{"algorithm", "random"}}},
                                   {"budget", {{"trials", 1}}}},
                                  train});
    spec["trial_timeout_s"] = 120;
    podium::testing::TempDir dir;
    const auto campaign = podium::testing::run_campaign_to_end(dir.path(), spec);
    const auto& cvae = campaign.trials.at("pose_cvae").at(0);
    EXPECT_EQ(campaign.artifact_names(cvae), (std::set<std::string>{"pose_cvae"}));
    EXPECT_GT(cvae.result_info["heldout_poses"].get<int>(), 0);
    EXPECT_TRUE(campaign.metric_names(cvae).count("pose_cvae_loss"));
    std::string file;
    for (const auto& a : campaign.store->artifacts(cvae.id))
      if (a.name == "pose_cvae") file = a.path;
    const auto vae = learn::PoseVae::from_file(fs::path(file).is_absolute() ? fs::path(file) : dir / file);
    EXPECT_EQ(vae->condition_size(), conditional ? 3u : 0u);
    const auto& t = campaign.trials.at("train").at(0);
    EXPECT_EQ(campaign.artifact_names(t), (std::set<std::string>{"policy", "pose_cvae", "trajectory", "trajectory_1", "curves"}));
    EXPECT_TRUE(campaign.metric_names(t).count("test/mean_r_task"));
  }
}

}  // namespace
}  // namespace podium::tasks::getup_curves
