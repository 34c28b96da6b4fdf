// The style curves' endpoint (GET /api/trials/ID/curves) against a getup_curves smoke campaign run
// by the real CLI: the train stage's `curves` artifact served parsed and equal to its file, every
// series as long as its time axis, each episode naming its motion; a malformed file refused with
// its JSON path; a trial without one 404. The train stage also sends the average return rate.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "campaign_spec.h"
#include "dashboard_support.h"
#include "podium/store/store.h"

namespace podium::web_dashboard {
namespace {

namespace fs = std::filesystem;
using base::Json;
using testing::RunningServer;

class StyleCurvesApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new podium::testing::TempDir();
    curves_ = testing::run_campaign(dir_->path(), podium::testing::stage_spec({.name = "curves",
                                                                               .seed = 5,
                                                                               .retries = 0,
                                                                               .trial_timeout_s = 300,
                                                                               .task = "getup_curves",
                                                                               .stage = "train",
                                                                               .config = {{"stage", "train"}},
                                                                               .trials = 2}));
    plain_ = testing::run_campaign(dir_->path(), testing::landscape_spec("plain", 2));
    server_ = new RunningServer(dir_->path() / "podium.db");
  }
  static void TearDownTestSuite() {
    delete server_;
    delete dir_;
  }
  static std::vector<store::TrialRecord> trials(std::int64_t campaign) {
    return store::Store::open(dir_->path() / "podium.db", store::Store::Access::read_only)->campaign_trials(campaign);
  }
  // The trial's artifacts by name (paths as the store holds them, relative ones under the test's folder).
  static std::map<std::string, fs::path> artifacts(std::int64_t trial) {
    std::map<std::string, fs::path> out;
    for (const auto& a : store::Store::open(dir_->path() / "podium.db", store::Store::Access::read_only)->artifacts(trial))
      out[a.name] = fs::path(a.path).is_absolute() ? fs::path(a.path) : dir_->path() / a.path;
    return out;
  }
  static inline podium::testing::TempDir* dir_ = nullptr;
  static inline RunningServer* server_ = nullptr;
  static inline std::int64_t curves_ = 0, plain_ = 0;
};

TEST_F(StyleCurvesApi, ServesTheTrainStagesCurvesParsedAndChecked) {
  const auto trial = trials(curves_).at(0);
  ASSERT_EQ(trial.state, "done") << trial.error;
  int status = 0;
  const Json doc = server_->get_json("/api/trials/" + std::to_string(trial.id) + "/curves", &status);
  ASSERT_EQ(status, 200) << doc;
  const auto files = artifacts(trial.id);
  EXPECT_EQ(doc, base::read_json_file(files.at("curves")));  // the file itself, parsed
  ASSERT_EQ(doc["episodes"].size(), 2u);                     // smoke records both shipped curves
  const double dt = 1.0 / doc["control_hz"].get<double>();
  std::set<std::string> names;
  for (const Json& e : doc["episodes"]) {
    names.insert(e["curve"]["name"].get<std::string>());
    EXPECT_EQ(files.count(e["trajectory"].get<std::string>()), 1u) << e["trajectory"];  // its motion is an artifact
    EXPECT_GT(e["curve"]["duration_s"].get<double>(), 0.0);
    const std::size_t n = e["t_s"].size();
    ASSERT_GT(n, 1u);
    for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(e["t_s"][i].get<double>(), static_cast<double>(i) * dt, 1e-9);
    for (const char* f : {"h_m", "theta_x_deg", "theta_z_deg"}) {
      EXPECT_EQ(e["curve"]["control_points"][f].size(), 9u) << f;
      for (const char* block : {"target", "achieved"}) EXPECT_EQ(e[block][f].size(), n) << block << " " << f;
      // At t = 0 the target is the first control point (the spline is clamped).
      EXPECT_NEAR(e["target"][f][0].get<double>(), e["curve"]["control_points"][f][0].get<double>(), 1e-6) << f;
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{"faceup", "facedown"}));
  EXPECT_EQ(doc["episodes"][0]["trajectory"], "trajectory");
  EXPECT_EQ(doc["episodes"][1]["trajectory"], "trajectory_1");
}

TEST_F(StyleCurvesApi, TheAverageReturnRateIsADeclaredRateMetric) {
  const auto trial = trials(curves_).at(0);
  const Json t = server_->get_json("/api/trials/" + std::to_string(trial.id));
  Json declared;
  for (const Json& m : t["metrics"])
    if (m["name"] == "test/average_return_rate") declared = m;
  ASSERT_FALSE(declared.is_null());
  EXPECT_EQ(declared["kind"], "learning_curve");
  EXPECT_EQ(declared["range"], Json({0, 1}));
  const Json series = server_->get_json("/api/trials/" + std::to_string(trial.id) + "/metrics?name=test/average_return_rate");
  ASSERT_EQ(series.size(), 1u);
  ASSERT_FALSE(series[0]["values"].empty());
  for (const Json& v : series[0]["values"]) {
    EXPECT_GT(v.get<double>(), 0.0);  // r_task > 0 at every step an episode runs
    EXPECT_LE(v.get<double>(), 1.0);
  }
}

TEST_F(StyleCurvesApi, AMalformedArtifactIsRefusedWithItsJsonPath) {
  const auto trial = trials(curves_).at(1);
  const fs::path file = artifacts(trial.id).at("curves");
  Json doc = base::read_json_file(file);
  doc["episodes"][1]["achieved"]["theta_z_deg"].erase(0);  // one value short of its time axis
  podium::testing::write_file(file, doc.dump());
  int status = 0;
  const Json error = server_->get_json("/api/trials/" + std::to_string(trial.id) + "/curves", &status);
  EXPECT_EQ(status, 500);
  const std::string message = error["error"];
  EXPECT_NE(message.find(fs::weakly_canonical(file).string()), std::string::npos) << message;
  EXPECT_NE(message.find("episodes[1].achieved.theta_z_deg: has "), std::string::npos) << message;
  EXPECT_NE(message.find("values where t_s has"), std::string::npos) << message;
}

TEST_F(StyleCurvesApi, ATrialWithoutCurvesIsNotFound) {
  int status = 0;
  const Json error = server_->get_json("/api/trials/" + std::to_string(trials(plain_).at(0).id) + "/curves", &status);
  EXPECT_EQ(status, 404);
  EXPECT_NE(error["error"].get<std::string>().find("no artifact \"curves\""), std::string::npos) << error;
}

}  // namespace
}  // namespace podium::web_dashboard
