// The getup_curves plugin through the real `podium` binary: the task conformance suite (its resume
// case kills a smoke trial mid-run and checks the resumed attempt's result and metrics equal an
// uninterrupted run's) and bad configs named at their JSON path.
#include <gtest/gtest.h>

#include "podium/base/json.h"
#include "podium/plugins/loader.h"
#include "process.h"
#include "task_conformance.h"

namespace podium::tasks::getup_curves {
namespace {

using base::Json;
namespace fs = std::filesystem;

PODIUM_TASK_CONFORMANCE(GetupCurves, {.task = "getup_curves",
                                      .long_config = {{"total_steps", 100'000'000}},
                                      .resume_config = {{"total_steps", 1024}},
                                      .kill_after_metric_points = 20,
                                      .resumes_from_checkpoint = true,
                                      .artifacts = {"policy", "trajectory", "curves"}});

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

}  // namespace
}  // namespace podium::tasks::getup_curves
