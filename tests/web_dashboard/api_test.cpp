// The JSON API against campaigns run by the real CLI (landscape smoke and the replay fixture),
// checked against the store's own typed reads.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "dashboard_support.h"
#include "podium/store/store.h"
#include "podium/store/summary.h"
#include "podium/store/writer_lock.h"

namespace podium::web_dashboard {
namespace {

using base::Json;
using testing::RunningServer;

class Api : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new podium::testing::TempDir();
    landscape_ = testing::run_campaign(dir_->path(), testing::landscape_spec("smoke", 120));
    replay_ = testing::run_campaign(dir_->path(), testing::replay_fixture_spec("swing", 4));
    handover_ = testing::run_campaign(dir_->path(), handover_spec(), 1);  // its "broken" stage fails it
    server_ = new RunningServer(dir_->path() / "podium.db");
  }
  static void TearDownTestSuite() {
    delete server_;
    delete dir_;
  }
  static std::unique_ptr<store::Store> store() {
    return store::Store::open(dir_->path() / "podium.db", store::Store::Access::read_only);
  }
  static inline podium::testing::TempDir* dir_ = nullptr;
  static inline RunningServer* server_ = nullptr;
  // Three stages: "discover" groups 40 trials into more than 10 strategies, "refine" is handed the
  // best trial of each (one each), "broken" the top 2 of refine (all to every trial), and fails.
  static Json handover_spec() {
    const auto stage = [](const char* name, Json config, Json budget) {
      return Json{{"name", name},
                  {"task", "landscape"},
                  {"preset", "smoke"},
                  {"config", std::move(config)},
                  {"search", {{"algorithm", "random"}}},
                  {"budget", {{"trials", std::move(budget)}}}};
    };
    Json discover = stage("discover", {{"artifact", true}, {"regions", 40}}, 40);
    discover["strategy_threshold"] = 0.05;
    Json refine = stage("refine", {{"dim", 2}}, {{"per_input", 1}});
    refine["inputs"] = {{"stage", "discover"}, {"select", "best_per_strategy"}, {"per_trial", "each"}};
    Json broken = stage("broken", {{"failures", {{{"mode", "throw"}}}}}, 2);
    broken["inputs"] = {{"stage", "refine"}, {"select", "top"}, {"k", 2}};
    return {{"name", "handover"},    {"seed", 5},
            {"workers", 2},          {"retries", 0},
            {"trial_timeout_s", 30}, {"stages", {discover, refine, broken}}};
  }
  static inline std::int64_t landscape_ = 0, replay_ = 0, handover_ = 0;
};

TEST_F(Api, CampaignListReportsStateProgressBestAndRate) {
  const Json list = server_->get_json("/api/campaigns");
  ASSERT_GE(list.size(), 2u);
  const Json& c = list[0];
  EXPECT_EQ(c["id"], landscape_);
  EXPECT_EQ(c["state"], "done");
  EXPECT_EQ(c["counts"]["done"], 120);
  EXPECT_DOUBLE_EQ(c["progress"].get<double>(), 1.0);
  EXPECT_GT(c["trials_per_minute"].get<double>(), 0.0);
  double best = -1e300;
  for (const auto& t : store()->campaign_trials(landscape_)) best = std::max(best, t.objectives[0].get<double>());
  EXPECT_DOUBLE_EQ(c["best_objective"].get<double>(), best);
  EXPECT_EQ(c["stages"][0]["task"], "landscape");
}

TEST_F(Api, CampaignIsFoundByIdOrName) {
  EXPECT_EQ(server_->get_json("/api/campaigns/swing")["id"], replay_);
  const Json detail = server_->get_json("/api/campaigns/" + std::to_string(landscape_));
  EXPECT_EQ(detail["name"], "smoke");
  EXPECT_EQ(detail["stages"][0]["description"]["features"].size(), 2u);
  EXPECT_EQ(detail["stages"][0]["counts"]["done"], 120);
  int status = 0;
  server_->get_json("/api/campaigns/no-such-campaign", &status);
  EXPECT_EQ(status, 404);
}

TEST_F(Api, TrialPagesCoverEveryTrialExactlyOnce) {
  std::set<std::int64_t> ids;
  for (int offset = 0; offset < 120; offset += 37) {
    const Json page = server_->get_json("/api/campaigns/smoke/trials?limit=37&offset=" + std::to_string(offset));
    EXPECT_EQ(page["total"], 120);
    for (const auto& t : page["trials"]) ids.insert(t["id"].get<std::int64_t>());
  }
  std::set<std::int64_t> expected;
  for (const auto& t : store()->campaign_trials(landscape_)) expected.insert(t.id);
  EXPECT_EQ(ids, expected);
}

TEST_F(Api, OrdersByObjectiveAndFiltersByState) {
  const Json page = server_->get_json("/api/campaigns/smoke/trials?order=objective&desc=1&limit=10&state=done");
  ASSERT_EQ(page["trials"].size(), 10u);
  for (std::size_t i = 1; i < 10; ++i)
    EXPECT_GE(page["trials"][i - 1]["objectives"][0].get<double>(), page["trials"][i]["objectives"][0].get<double>());
  EXPECT_EQ(page["trials"][0]["objectives"][0], server_->get_json("/api/campaigns/smoke")["best_objective"]);
  EXPECT_EQ(server_->get_json("/api/campaigns/smoke/trials?state=failed")["total"], 0);
  EXPECT_EQ(server_->get_json("/api/campaigns/smoke/trials?stage=0")["total"], 120);
  EXPECT_EQ(server_->get_json("/api/campaigns/smoke/trials?stage=1")["total"], 0);
}

TEST_F(Api, PointsHaveOnePointPerDoneTrialAndStrideWhenCapped) {
  const Json all = server_->get_json("/api/campaigns/smoke/points");
  EXPECT_EQ(all["total"], 120);
  EXPECT_EQ(all["columns"]["id"].size(), 120u);
  EXPECT_EQ(all["columns"]["features"][0].size(), 2u);
  const Json capped = server_->get_json("/api/campaigns/smoke/points?max_points=50");
  EXPECT_EQ(capped["total"], 120);
  EXPECT_EQ(capped["columns"]["id"].size(), 40u);  // every 3rd of 120
  // The columns are written as text: each value is exactly the trial's.
  const Json& cols = all["columns"];
  for (const std::size_t i : {0u, 57u, 119u}) {
    const Json t = server_->get_json("/api/trials/" + std::to_string(cols["id"][i].get<std::int64_t>()));
    EXPECT_EQ(cols["objective"][i], t["objectives"][0]);
    EXPECT_EQ(cols["features"][i], t["features"]);
    EXPECT_EQ(cols["strategy"][i], t["strategy"]);
    EXPECT_EQ(cols["index"][i], t["index"]);
    EXPECT_EQ(cols["stage"][i], t["stage"]);
    EXPECT_EQ(cols["finished_at"][i], t["finished_at"]);
    EXPECT_EQ(cols["step"][i], t["info"].value("step", ""));
  }
}

TEST_F(Api, TrialDetailHasAttemptsArtifactsAndMetrics) {
  const auto trial = store()->campaign_trials(landscape_)[17];
  const Json t = server_->get_json("/api/trials/" + std::to_string(trial.id));
  EXPECT_EQ(t["campaign_id"], landscape_);
  EXPECT_EQ(t["index"], 17);
  EXPECT_EQ(t["params"], trial.params);
  EXPECT_EQ(t["seed"], std::to_string(trial.seed));
  ASSERT_EQ(t["attempt_list"].size(), 1u);
  EXPECT_EQ(t["attempt_list"][0]["state"], "done");
  ASSERT_EQ(t["artifacts"].size(), 1u);
  EXPECT_EQ(t["artifacts"][0]["name"], "result");

  auto client = server_->client();
  const auto r = client.Get(t["artifacts"][0]["url"].get<std::string>().c_str());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  std::ifstream in(t["artifacts"][0]["path"].get<std::string>(), std::ios::binary);
  EXPECT_EQ(r->body, std::string(std::istreambuf_iterator<char>(in), {}));
  EXPECT_NE(r->get_header_value("Content-Disposition").find("attachment"), std::string::npos);

  const Json metrics = server_->get_json("/api/trials/" + std::to_string(trial.id) + "/metrics");
  ASSERT_EQ(metrics.size(), 1u);
  EXPECT_EQ(metrics[0]["name"], "trace");
  EXPECT_EQ(metrics[0]["steps"].size(), 5u);
  EXPECT_DOUBLE_EQ(metrics[0]["values"][4].get<double>(), trial.objectives[0].get<double>());
}

// Artifacts download as campaign_stage-index_artifact.ext: a trial's files, and those of different
// trials, never share a name.
TEST_F(Api, ArtifactsDownloadUnderTheirCampaignStageTrialAndName) {
  const auto trials = store()->campaign_trials(landscape_);
  std::set<std::string> names;
  for (const auto& trial : {trials[3], trials[17]}) {
    const Json t = server_->get_json("/api/trials/" + std::to_string(trial.id));
    EXPECT_EQ(t["campaign_name"], "smoke");
    const std::string expected = "smoke_explore-" + std::to_string(trial.index) + "_result" +
                                 std::filesystem::path(t["artifacts"][0]["path"].get<std::string>()).extension().string();
    EXPECT_EQ(t["artifacts"][0]["download_name"], expected);
    auto client = server_->client();
    const auto r = client.Get(t["artifacts"][0]["url"].get<std::string>().c_str());
    ASSERT_TRUE(r);
    EXPECT_EQ(r->get_header_value("Content-Disposition"), "attachment; filename=\"" + expected + "\"");
    names.insert(expected);
  }
  EXPECT_EQ(names.size(), 2u);
}

// Metrics carry their plot's shape: the landscape's trace declares its axis; the replay fixture
// declares none, and reads as a learning curve over "step".
TEST_F(Api, MetricsDeclareTheirAxisAndKindWithAFallback) {
  const Json landscape = server_->get_json("/api/trials/" + std::to_string(store()->campaign_trials(landscape_)[0].id));
  ASSERT_EQ(landscape["metrics"].size(), 1u);
  EXPECT_EQ(landscape["metrics"][0]["x"]["name"], "iteration");
  EXPECT_EQ(landscape["metrics"][0]["kind"], "learning_curve");
  const Json fixture = server_->get_json("/api/trials/" + std::to_string(store()->campaign_trials(replay_)[0].id));
  ASSERT_FALSE(fixture["metrics"].empty());
  for (const auto& m : fixture["metrics"]) {
    EXPECT_EQ(m["x"]["name"], "step") << m;
    EXPECT_EQ(m["kind"], "learning_curve") << m;
  }
  const Json detail = server_->get_json("/api/campaigns/" + std::to_string(landscape_));
  EXPECT_EQ(detail["stages"][0]["description"]["metrics"], landscape["metrics"]);
}

// Each stage's best done trial by its own objective (no number across stages), and whether a
// strategy's representative recorded a motion (a landscape's did not: no replay link).
TEST_F(Api, StagesNameTheirBestTrialAndStrategiesSayWhetherTheyMove) {
  const Json list = server_->get_json("/api/campaigns");
  const Json& c = list[0];
  const Json& best = c["stages"][0]["best"];
  EXPECT_EQ(best["objective"], "objective");
  EXPECT_DOUBLE_EQ(best["value"].get<double>(), c["best_objective"].get<double>());
  const Json t = server_->get_json("/api/trials/" + std::to_string(best["id"].get<std::int64_t>()));
  EXPECT_EQ(best["name"], t["name"]);
  EXPECT_EQ(t["objectives"][0], best["value"]);
  for (const auto& row : server_->get_json("/api/campaigns/" + std::to_string(landscape_) + "/strategies")) {
    EXPECT_EQ(row["motion"], false) << row;
    EXPECT_TRUE(row["technique"].is_null()) << row;
  }
  const Json moving = server_->get_json("/api/campaigns/" + std::to_string(replay_) + "/strategies");
  ASSERT_FALSE(moving.empty());
  for (const auto& row : moving) EXPECT_EQ(row["motion"], true) << row;
}

// The summary panel's and the comparison view's documents are the orchestrator's summary library's
// (what `podium summary --json` prints); campaigns are named by id or name, a bad list is refused.
TEST_F(Api, SummaryAndComparisonAreTheSummaryLibrarysDocuments) {
  const Json summary = server_->get_json("/api/campaigns/smoke/summary");
  EXPECT_EQ(summary["campaign"]["id"], landscape_);
  ASSERT_EQ(summary["stages"].size(), 1u);
  EXPECT_EQ(summary["stages"][0]["trials"]["done"], 120);
  EXPECT_EQ(summary["stages"][0]["best"]["id"], server_->get_json("/api/campaigns")[0]["stages"][0]["best"]["id"]);
  const Json both = server_->get_json("/api/compare?campaigns=" + std::to_string(landscape_) + ",swing");
  ASSERT_EQ(both["campaigns"].size(), 2u);
  EXPECT_EQ(both["campaigns"][0], summary);
  EXPECT_EQ(both["campaigns"][1]["campaign"]["id"], replay_);
  int status = 0;
  for (const char* bad : {"/api/compare", "/api/compare?campaigns=", "/api/compare?campaigns=smoke,,swing",
                          "/api/compare?campaigns=1,1,1,1,1,1,1,1,1"}) {
    server_->get_json(bad, &status);
    EXPECT_EQ(status, 400) << bad;
  }
  server_->get_json("/api/compare?campaigns=smoke,no-such-campaign", &status);
  EXPECT_EQ(status, 404);
}

TEST_F(Api, TrajectoryEndpointServesTheReplayArtifact) {
  const auto trial = store()->campaign_trials(replay_)[0];
  auto client = server_->client();
  const auto r = client.Get(("/api/trials/" + std::to_string(trial.id) + "/trajectory").c_str());
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  std::istringstream lines(r->body);  // sim/'s JSON-lines format: a header, then one frame per line
  std::string line;
  std::getline(lines, line);
  const Json header = Json::parse(line);
  EXPECT_EQ(header["format"], "podium-trajectory");
  int frames = 0;
  while (std::getline(lines, line)) {
    EXPECT_EQ(Json::parse(line)["links"].size(), header["links"].size());
    ++frames;
  }
  EXPECT_EQ(frames, 90);
  // Another trajectory artifact by name; a name that is no trajectory is refused.
  const auto fast = client.Get(("/api/trials/" + std::to_string(trial.id) + "/trajectory?artifact=trajectory_fast").c_str());
  ASSERT_TRUE(fast);
  EXPECT_EQ(fast->status, 200);
  // The fixture writes it as the same frames from t = 2 s (a get-up's fast run starts after its fall).
  std::istringstream main_lines(r->body), fast_lines(fast->body);
  std::string fast_line;
  int fast_frames = 0;
  while (std::getline(main_lines, line) && std::getline(fast_lines, fast_line)) {
    Json frame = Json::parse(line), fast_frame = Json::parse(fast_line);
    if (frame.contains("t")) {
      EXPECT_NEAR(fast_frame["t"].get<double>(), frame["t"].get<double>() + 2.0, 1e-12);
      frame.erase("t"), fast_frame.erase("t"), ++fast_frames;
    }
    EXPECT_EQ(fast_frame, frame);
  }
  EXPECT_EQ(fast_frames, 90);
  const auto other = client.Get(("/api/trials/" + std::to_string(trial.id) + "/trajectory?artifact=policy").c_str());
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 400);
  int status = 0;
  const auto landscape_trial = store()->campaign_trials(landscape_)[0];
  server_->get_json("/api/trials/" + std::to_string(landscape_trial.id) + "/trajectory", &status);
  EXPECT_EQ(status, 404);  // landscape trials record no motion
}

TEST_F(Api, VersionChangesOnlyWhenTheDatabaseChanges) {
  const auto before = server_->get_json("/api/version")["data_version"];
  EXPECT_EQ(server_->get_json("/api/version")["data_version"], before);
  // A write by another process: a campaign is queued.
  podium::testing::write_file(dir_->path() / "extra.json", testing::landscape_spec("extra", 3).dump());
  const auto r = podium::testing::run_podium({"submit", "extra.json"}, dir_->path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(server_->get_json("/api/version")["data_version"], before);
  EXPECT_EQ(server_->get_json("/api/campaigns/extra")["state"], "queued");
}

TEST_F(Api, ServesTheFrontEndAndRefusesUnknownPaths) {
  auto client = server_->client();
  for (const char* page : {"/", "/index.html", "/campaign.html", "/trial.html", "/replay.html", "/vendor/three.module.js",
                           "/vendor/uPlot.iife.min.js", "/vendor/OrbitControls.js"}) {
    const auto r = client.Get(page);
    ASSERT_TRUE(r) << page;
    EXPECT_EQ(r->status, 200) << page;
    EXPECT_FALSE(r->body.empty()) << page;
  }
  EXPECT_EQ(client.Get("/nope.html")->status, 404);
  EXPECT_EQ(client.Get("/api/nope")->status, 404);
  EXPECT_EQ(client.Get("/api/trials/999999")->status, 404);
}

// Strategy ids restart per stage: the list counts them per stage, never summed over stages.
TEST_F(Api, StrategiesAreCountedPerStage) {
  const auto stages = store()->stages(handover_);
  const Json list = server_->get_json("/api/campaigns");
  const auto c = std::find_if(list.begin(), list.end(), [](const Json& j) { return j["id"] == handover_; });
  ASSERT_NE(c, list.end());
  EXPECT_FALSE(c->contains("strategies"));
  for (const auto& st : stages) {
    std::set<std::int64_t> ids;
    for (const auto& t : store()->trials(st.id))
      if (t.strategy) ids.insert(*t.strategy);
    EXPECT_EQ((*c)["stages"][st.index]["strategies"], ids.size()) << st.name;
  }
  EXPECT_GT((*c)["stages"][0]["strategies"].get<int>(), 10);
  EXPECT_EQ((*c)["stages"][2]["strategies"], 0);
}

// Each stage's true state, why it failed, what it was handed, and the task's config keys.
TEST_F(Api, StagesShowStateErrorInputsAndTaskConfig) {
  const auto stages = store()->stages(handover_);
  const Json c = server_->get_json("/api/campaigns/" + std::to_string(handover_));
  EXPECT_EQ(c["state"], "failed");
  EXPECT_EQ(c["scheduler"], "none");
  const Json& s = c["stages"];
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0]["state"], "done");
  EXPECT_EQ(s[0]["error"], "");
  EXPECT_TRUE(s[0]["inputs"].is_null());
  EXPECT_TRUE(s[0]["input_trials"].is_null());
  EXPECT_EQ(s[1]["inputs"]["select"], "best_per_strategy");
  EXPECT_EQ(s[1]["inputs"]["per_trial"], "each");
  EXPECT_EQ(s[1]["inputs"]["stages"], Json::array({"discover"}));
  EXPECT_EQ(s[1]["input_trials"], s[0]["strategies"]);  // the best trial of each strategy
  EXPECT_EQ(s[1]["input_trials"], stages[1].input_trials->size());
  EXPECT_EQ(s[2]["state"], "failed");
  EXPECT_EQ(s[2]["error"], stages[2].error);
  EXPECT_NE(s[2]["error"].get<std::string>().find("all 2 trials failed"), std::string::npos) << s[2]["error"];
  EXPECT_EQ(s[2]["input_trials"], 2);
  // The task's config description: key, type, default, allowed values.
  const Json& config = s[0]["description"]["config"];
  const auto family = std::find_if(config.begin(), config.end(), [](const Json& k) { return k["key"] == "family"; });
  ASSERT_NE(family, config.end()) << config.dump();
  EXPECT_EQ((*family)["type"], "string");
  EXPECT_EQ((*family)["default"], "basins");
  EXPECT_NE(std::find((*family)["choices"].begin(), (*family)["choices"].end(), "voronoi"), (*family)["choices"].end());
}

// A trial is named "<stage>/<index>" on every document that refers to it.
TEST_F(Api, TrialsAreNamedByStageAndIndex) {
  const Json page = server_->get_json("/api/campaigns/handover/trials?stage=1&limit=3&offset=2");
  ASSERT_EQ(page["trials"].size(), 3u);
  EXPECT_EQ(page["trials"][0]["name"], "refine/2");
  const Json t = server_->get_json("/api/trials/" + std::to_string(page["trials"][1]["id"].get<std::int64_t>()));
  EXPECT_EQ(t["name"], "refine/3");
  for (const auto& row : server_->get_json("/api/campaigns/handover/strategies")) {
    const Json rep = server_->get_json("/api/trials/" + std::to_string(row["representative_trial"].get<std::int64_t>()));
    EXPECT_EQ(row["representative_name"], rep["name"]);
    EXPECT_EQ(rep["stage"], row["stage"]);
  }
}

// The trial page names (and links by id) the earlier trials a trial was handed: per_trial "each"
// the one its info names, "all" every selected one.
TEST_F(Api, TrialDetailNamesTheTrialsItWasHanded) {
  const auto stages = store()->stages(handover_);
  for (const auto& t : store()->trials(stages[1].id)) {
    const Json d = server_->get_json("/api/trials/" + std::to_string(t.id));
    ASSERT_EQ(d["inputs"].size(), 1u);
    const Json& expected = (*stages[1].input_trials)[t.info["input"].get<std::size_t>()];
    const Json& input = d["inputs"][0];
    EXPECT_EQ(input["name"], "discover/" + std::to_string(expected["trial_index"].get<int>()));
    const Json earlier = server_->get_json("/api/trials/" + std::to_string(input["id"].get<std::int64_t>()));
    EXPECT_EQ(earlier["name"], input["name"]);
    EXPECT_EQ(earlier["strategy"], input["strategy"]);
  }
  const Json broken = server_->get_json("/api/trials/" + std::to_string(store()->trials(stages[2].id)[0].id));
  ASSERT_EQ(broken["inputs"].size(), 2u);
  EXPECT_EQ(broken["inputs"][0]["stage"], 1);
  const Json first = server_->get_json("/api/campaigns/handover/trials?stage=0&limit=1");
  EXPECT_EQ(server_->get_json("/api/trials/" + std::to_string(first["trials"][0]["id"].get<std::int64_t>()))["inputs"],
            Json::array());
}

// Every trial the scheduler ran has its log in its folder, served as text: a done one its
// attempt's header line, a failed one also the line that says why; the page asks for its end.
TEST_F(Api, ATrialsLogIsServedAndAFailedOneSaysWhy) {
  const auto stages = store()->stages(handover_);
  auto client = server_->client();
  const auto log_of = [&](std::int64_t trial_id) {
    const std::string url = server_->get_json("/api/trials/" + std::to_string(trial_id))["log_url"];
    EXPECT_EQ(url, "/api/trials/" + std::to_string(trial_id) + "/log");
    const auto r = client.Get(url.c_str());
    EXPECT_TRUE(r && r->status == 200) << url;
    EXPECT_EQ(r ? r->get_header_value("Content-Type") : "", "text/plain; charset=utf-8");
    return r ? r->body : "";
  };
  const auto done = store()->trials(stages[0].id).at(0);
  EXPECT_EQ(log_of(done.id).rfind("podium: attempt 1 started ", 0), 0u) << log_of(done.id);
  const auto failed = store()->trials(stages[2].id).at(0);
  ASSERT_EQ(failed.state, "failed");
  const std::string text = log_of(failed.id);
  EXPECT_EQ(text.rfind("podium: attempt 1 started ", 0), 0u) << text;
  EXPECT_NE(text.find("podium error: attempt failed: injected failure (throw)"), std::string::npos) << text;
  // The page's request: the last bytes only.
  const auto tail = client.Get(("/api/trials/" + std::to_string(failed.id) + "/log").c_str(), {{"Range", "bytes=-20"}});
  ASSERT_TRUE(tail);
  EXPECT_EQ(tail->status, 206);
  EXPECT_EQ(tail->body, text.substr(text.size() - 20));
}

// A running campaign with no scheduler alive (killed with -9: nothing was written) is "stopped",
// as `podium status` shows it; a held writer lock is a live scheduler.
// A campaign's summary is kept while its own campaign is unchanged (a commit to another campaign
// leaves it), and is made again as soon as one of its trials finishes or its state changes: each
// answer equals the summary library's document made afresh.
TEST(ApiSummaryCache, FollowsItsOwnCampaignOnly) {
  podium::testing::TempDir dir;
  const auto db = dir / "podium.db";
  auto writer = store::Store::open(db, store::Store::Access::read_write);
  store::NewStage stage{"explore", "landscape", "random"};
  stage.description = {{"params", Json::array()},
                       {"features", Json::array({{{"name", "f0"}, {"low", 0}, {"high", 1}}})},
                       {"objectives", {"objective"}}};
  stage.budget_trials = 10;
  const auto watched = writer->add_campaign("watched", Json::object(), 1, "", {stage});
  const auto other = writer->add_campaign("other", Json::object(), 1, "", {stage});
  const auto finish = [&](std::int64_t campaign, std::int64_t index, double objective, std::int64_t strategy) {
    const auto t = writer->add_trial(writer->stages(campaign)[0].id, index, Json::object(), Json::object(), Json::object(), 1);
    writer->complete_trial(t, {objective}, {"f0"}, {0.5}, Json::object(), {});
    writer->set_trial_strategy(t, strategy);
  };
  finish(watched, 0, 0.5, 4);
  RunningServer server(db);
  const std::string url = "/api/campaigns/" + std::to_string(watched) + "/summary";
  const auto fresh = [&] {
    const auto reader = store::Store::open(db, store::Store::Access::read_only);
    return store::campaign_summary(*reader, watched);
  };
  const Json first = server.get_json(url);
  EXPECT_EQ(first, fresh());
  EXPECT_EQ(first["stages"][0]["trials"]["done"], 1);

  finish(other, 0, 0.9, 2);  // another campaign: the watched one's summary stands
  writer->add_event(other, "note", Json::object());
  EXPECT_EQ(server.get_json(url), first);
  EXPECT_EQ(server.get_json(url), fresh());

  finish(watched, 1, 0.8, 7);  // a trial of its own finishes: a new best and a second strategy
  const Json second = server.get_json(url);
  EXPECT_EQ(second, fresh());
  EXPECT_EQ(second["stages"][0]["trials"]["done"], 2);
  EXPECT_EQ(second["stages"][0]["best"]["index"], 1);
  EXPECT_EQ(second["stages"][0]["strategies"].size(), 2u);

  writer->set_campaign_state(watched, "cancelled");  // its state: the stage shows it
  const Json third = server.get_json(url);
  EXPECT_EQ(third, fresh());
  EXPECT_EQ(third["campaign"]["state"], "cancelled");
  const Json both = server.get_json("/api/compare?campaigns=" + std::to_string(watched) + "," + std::to_string(other));
  EXPECT_EQ(both["campaigns"][0], third);
}

TEST(ApiStates, RunningWithoutASchedulerIsStopped) {
  podium::testing::TempDir dir;
  const auto id = testing::run_campaign(dir.path(), testing::landscape_spec("killed", 3));
  const auto db = dir / "podium.db";
  const auto mark_running = [&] {  // and a new event: a change, so the server's cached answers are not reused
    auto s = store::Store::open(db, store::Store::Access::read_write);
    s->add_event(id, "test", Json::object());
    s->set_campaign_state(id, "running");
    s->set_stage_state(s->stages(id)[0].id, "running");  // killed mid-stage
  };
  RunningServer server(db);
  {
    const store::WriterLock lock(db);
    mark_running();
    const Json c = server.get_json("/api/campaigns/" + std::to_string(id));
    EXPECT_EQ(c["state"], "running");
    EXPECT_EQ(c["scheduler"], "alive");
  }
  mark_running();
  const Json c = server.get_json("/api/campaigns/" + std::to_string(id));
  EXPECT_EQ(c["state"], "stopped");
  EXPECT_EQ(c["scheduler"], "none");
  EXPECT_EQ(c["stages"][0]["state"], "stopped");
}

// A page lists each trial as the same document the trial's own endpoint gives (pages copy the
// stored JSON text instead of building it).
TEST_F(Api, PageTrialsAreTheTrialDocuments) {
  const Json page = server_->get_json("/api/campaigns/smoke/trials?limit=5&offset=40");
  ASSERT_EQ(page["trials"].size(), 5u);
  for (const auto& t : page["trials"]) {
    Json detail = server_->get_json("/api/trials/" + std::to_string(t["id"].get<std::int64_t>()));
    Json listed = Json::object();
    for (const auto& [key, value] : t.items()) listed[key] = detail.at(key);
    EXPECT_EQ(t, listed);
  }
}

// The dashboard reads counts and strategies from the count rows the store keeps; after a campaign
// with retried, failed and cancelled trials they must equal a recount of the trials.
TEST(ApiRecount, SummaryAndStrategiesEqualARecountAfterRetriesFailuresAndCancel) {
  podium::testing::TempDir dir;
  Json spec = testing::landscape_spec("faulty", 400,
                                      {{"sleep_s", 0.3},
                                       {"failures",
                                        {{{"mode", "throw"}, {"trials", {1, 4}}, {"attempts", 1}},
                                         {{"mode", "throw"}, {"trials", {2}}},
                                         {{"mode", "hang"}, {"trials", {3}}}}}});
  podium::testing::write_file(dir / "spec.json", spec.dump());
  const auto submit = podium::testing::run_podium({"submit", "spec.json"}, dir.path());
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const std::string id = std::to_string(std::stoll(submit.out));
  const pid_t scheduler = podium::testing::spawn_podium({"run", "--workers", "2"}, dir.path());
  // Until trial 2 failed and 3 are done (at most a minute): trial 3 hangs, and results are told
  // in trial order, so with 2 workers only trials 0-4 run before it times out.
  for (int i = 0; i < 600; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const auto status = podium::testing::run_podium({"status", id, "--json"}, dir.path());
    if (status.exit_code != 0) continue;
    const Json s = Json::parse(status.out);
    if (s.value("done", 0) >= 3 && s.value("failed", 0) >= 1) break;
  }
  ASSERT_EQ(podium::testing::run_podium({"cancel", id}, dir.path()).exit_code, 0);
  ASSERT_EQ(podium::testing::wait_process(scheduler), 0);

  const auto trials = store::Store::open(dir / "podium.db", store::Store::Access::read_only)->campaign_trials(std::stoll(id));
  std::map<std::string, std::int64_t> states;
  std::map<std::int64_t, std::pair<std::int64_t, const store::TrialRecord*>> strategies;  // size, best trial
  double best = -1e300;
  bool retried = false;
  for (const auto& t : trials) {
    ++states[t.state];
    retried = retried || t.attempts > 1;
    if (t.state == "done") best = std::max(best, t.objectives[0].get<double>());
    if (!t.strategy) continue;
    auto& [size, rep] = strategies[*t.strategy];
    ++size;
    if (!rep || t.objectives[0].get<double>() > rep->objectives[0].get<double>()) rep = &t;  // earliest of equals
  }
  EXPECT_TRUE(retried);
  EXPECT_EQ(states["failed"], 1);
  EXPECT_GE(states["cancelled"], 1) << Json(states).dump();

  RunningServer server(dir / "podium.db");
  const Json c = server.get_json("/api/campaigns/" + id);
  EXPECT_EQ(c["state"], "cancelled");
  EXPECT_EQ(c["counts"]["total"], static_cast<std::int64_t>(trials.size()));
  for (const char* state : {"done", "failed", "cancelled", "running"}) EXPECT_EQ(c["counts"][state], states[state]) << state;
  EXPECT_EQ(c["counts"]["pending"], states["pending"] + states["interrupted"]);
  EXPECT_EQ(c["stages"][0]["counts"], c["counts"]);
  EXPECT_DOUBLE_EQ(c["best_objective"].get<double>(), best);
  const Json table = server.get_json("/api/campaigns/" + id + "/strategies");
  EXPECT_EQ(c["stages"][0]["strategies"], table.size());
  ASSERT_EQ(table.size(), strategies.size());
  for (const auto& row : table) {
    const auto& [size, rep] = strategies.at(row["strategy"].get<std::int64_t>());
    EXPECT_EQ(row["trials"], size);
    EXPECT_EQ(row["representative_trial"], rep->id);
    EXPECT_DOUBLE_EQ(row["best_objective"].get<double>(), rep->objectives[0].get<double>());
  }
}

}  // namespace
}  // namespace podium::web_dashboard
