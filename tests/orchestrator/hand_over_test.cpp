// Stage hand-over end to end: real `podium submit` and `podium run`, a real
// SQLite file, and the probe task (tests/plugins/probe_task.cpp), which reports in its result
// info the inputs that reached it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <set>
#include <thread>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

using base::Json;
using podium::testing::file_bytes;
using podium::testing::run_podium;
using podium::testing::TempDir;
using store::Store;

Json probe_stage(const std::string& name, const std::string& algorithm, const Json& trials, const Json& config = Json::object(),
                 const Json& search_config = Json::object()) {
  return {{"name", name},
          {"task", "probe"},
          {"config", config},
          {"search", {{"algorithm", algorithm}, {"config", search_config}}},
          {"budget", {{"trials", trials}}}};
}

Json campaign(const std::string& name, const Json& stages, int retries = 1) {
  return {{"name", name}, {"seed", 7}, {"workers", 2}, {"retries", retries}, {"trial_timeout_s", 60}, {"stages", stages}};
}

std::int64_t submit(const TempDir& dir, const Json& spec) { return std::stoll(podium::testing::submit_spec(dir.path(), spec)); }

// `podium run` to the end; it exits 1 when a campaign it ran failed.
void run(const TempDir& dir, int exit_code = 0) {
  const auto r = run_podium({"run"}, dir.path());
  ASSERT_EQ(r.exit_code, exit_code) << r.err;
}

std::unique_ptr<Store> open_store(const TempDir& dir) { return Store::open(dir / "podium.db", Store::Access::read_only); }

std::vector<store::TrialRecord> stage_trials(const Store& s, std::int64_t campaign, int stage) {
  return s.trials(s.stages(campaign).at(stage).id);
}

// What the probe saw of an input, for comparison with the trial it came from.
Json expected_input(const Store& s, const std::string& stage_name, int stage_index, const store::TrialRecord& t) {
  Json artifacts = Json::object();
  for (const auto& a : s.artifacts(t.id)) artifacts[a.name] = {{"path", a.path}, {"absolute", true}, {"exists", true}};
  return {{"stage", stage_name},
          {"stage_index", stage_index},
          {"trial_index", t.index},
          {"params", t.params},
          {"objectives", t.objectives},
          {"features", t.features},
          {"strategy", t.strategy ? Json(*t.strategy) : Json(nullptr)},
          {"artifacts", artifacts},
          {"info", t.result_info.is_object() ? t.result_info : Json::object()}};
}

double objective(const store::TrialRecord& t) { return t.objectives[0].get<double>(); }

TEST(HandOver, InputsReachTheTrialsOfEveryAlgorithm) {
  TempDir dir;
  std::map<std::string, std::int64_t> ids;
  for (const std::string algorithm : {"random", "bds", "novelty", "cmaes", "novel_policy"}) {
    Json second = probe_stage("use", algorithm, 4, Json::object(),
                              algorithm == "novel_policy" ? Json{{"trials_per_input", 1}} : Json::object());
    second["inputs"] = {{"stage", "explore"}};
    ids[algorithm] = submit(dir, campaign(algorithm, {probe_stage("explore", "random", 4), second}));
  }
  run(dir);
  auto s = open_store(dir);
  for (const auto& [algorithm, id] : ids) {
    SCOPED_TRACE(algorithm);
    EXPECT_EQ(s->campaign(id)->state, "done");
    Json expected = Json::array();
    for (const auto& t : stage_trials(*s, id, 0)) expected.push_back(expected_input(*s, "explore", 0, t));
    ASSERT_EQ(expected.size(), 4u);
    const auto used = stage_trials(*s, id, 1);
    ASSERT_EQ(used.size(), 4u);
    for (const auto& t : used) {
      EXPECT_EQ(t.state, "done");
      EXPECT_EQ(t.result_info.at("inputs"), expected) << "trial " << t.index;
      EXPECT_TRUE(t.result_info.at("work_dir_absolute").get<bool>());
    }
    const auto stored = s->stages(id)[1].input_trials;  // resolved once, when the stage started
    ASSERT_TRUE(stored.has_value());
    EXPECT_EQ(stored->size(), 4u);
  }
  // Novel-policy seeking keeps its own use of them: one trial at each input's parameters.
  std::set<std::string> at;
  for (const auto& t : stage_trials(*s, ids["novel_policy"], 1)) at.insert(t.params.dump());
  std::set<std::string> inputs;
  for (const auto& t : stage_trials(*s, ids["novel_policy"], 0)) inputs.insert(t.params.dump());
  EXPECT_EQ(at, inputs);
}

TEST(HandOver, SelectModesPickTheDocumentedTrials) {
  TempDir dir;
  auto using_inputs = [](const std::string& name, const Json& inputs) {
    Json stage = probe_stage(name, "random", 1);
    stage["inputs"] = inputs;
    return stage;
  };
  const auto id =
      submit(dir, campaign("select", {probe_stage("explore", "random", 12), probe_stage("other", "random", 3),
                                      using_inputs("best", {{"stage", "explore"}, {"select", "best"}}),
                                      using_inputs("top", {{"stage", "explore"}, {"select", "top"}, {"k", 3}}),
                                      using_inputs("per_strategy", {{"stage", "explore"}, {"select", "best_per_strategy"}}),
                                      using_inputs("two", {{"stage", {"other", "explore"}}, {"select", "best"}})}));
  run(dir);
  auto s = open_store(dir);
  ASSERT_EQ(s->campaign(id)->state, "done");
  auto explore = stage_trials(*s, id, 0);
  const auto other = stage_trials(*s, id, 1);
  auto received = [&](int stage) {
    std::vector<std::int64_t> out;
    const auto trials = stage_trials(*s, id, stage);
    for (const auto& in : trials.at(0).result_info.at("inputs")) out.push_back(in["trial_index"]);
    return out;
  };
  auto ranked = explore;
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return objective(a) > objective(b); });
  EXPECT_EQ(received(2), (std::vector<std::int64_t>{ranked[0].index}));
  EXPECT_EQ(received(3), (std::vector<std::int64_t>{ranked[0].index, ranked[1].index, ranked[2].index}));
  // The best of each strategy, by strategy id.
  std::map<std::int64_t, std::int64_t> best_of;
  for (const auto& t : ranked)
    if (!best_of.count(*t.strategy)) best_of[*t.strategy] = t.index;
  std::vector<std::int64_t> per_strategy;
  for (const auto& [strategy, index] : best_of) per_strategy.push_back(index);
  ASSERT_GE(per_strategy.size(), 2u) << "the probe's 12 trials should form several strategies";
  EXPECT_EQ(received(4), per_strategy);
  // Several stages: each one's selection, in the order named.
  const auto best_other =
      *std::max_element(other.begin(), other.end(), [](const auto& a, const auto& b) { return objective(a) < objective(b); });
  const Json two = stage_trials(*s, id, 5).at(0).result_info.at("inputs");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0]["stage"], "other");
  EXPECT_EQ(two[0]["trial_index"], best_other.index);
  EXPECT_EQ(two[1]["stage"], "explore");
  EXPECT_EQ(two[1]["trial_index"], ranked[0].index);
}

TEST(HandOver, EachTrialGetsOneInputAndThePerInputBudget) {
  TempDir dir;
  Json each = probe_stage("each", "random", {{"per_input", 2}});
  each["inputs"] = {{"stage", "explore"}, {"select", "top"}, {"k", 3}, {"per_trial", "each"}};
  const auto id = submit(dir, campaign("each", {probe_stage("explore", "random", 5), each}));
  run(dir);
  auto s = open_store(dir);
  ASSERT_EQ(s->campaign(id)->state, "done");
  const auto stage = s->stages(id).at(1);
  EXPECT_EQ(stage.budget_trials, 6);
  const Json handed = stage.input_trials.value();
  ASSERT_EQ(handed.size(), 3u);
  const auto trials = stage_trials(*s, id, 1);
  ASSERT_EQ(trials.size(), 6u);
  for (const auto& t : trials) {
    const Json inputs = t.result_info.at("inputs");
    ASSERT_EQ(inputs.size(), 1u) << t.index;
    EXPECT_EQ(inputs[0]["trial_index"], handed[t.index % 3]["trial_index"]) << t.index;
    EXPECT_EQ(t.info.at("input"), t.index % 3);
  }
}

// Under novel-policy seeking a trial's one input is the one it seeks a novel policy for (its
// proposals run at that input's parameters), not trial index mod n.
TEST(HandOver, EachUnderNovelPolicyGivesATrialTheInputItWorksOn) {
  TempDir dir;
  Json novel = probe_stage("novel", "novel_policy", {{"per_input", 2}}, Json::object(), {{"trials_per_input", 2}});
  novel["inputs"] = {{"stage", "explore"}, {"select", "top"}, {"k", 3}, {"per_trial", "each"}};
  const auto id = submit(dir, campaign("novel", {probe_stage("explore", "random", 5), novel}));
  run(dir);
  auto s = open_store(dir);
  ASSERT_EQ(s->campaign(id)->state, "done");
  const Json handed = s->stages(id).at(1).input_trials.value();
  const auto trials = stage_trials(*s, id, 1);
  ASSERT_EQ(trials.size(), 6u);
  bool not_mod_n = false;
  for (const auto& t : trials) {
    const auto input = t.info.at("input").get<std::size_t>();
    not_mod_n = not_mod_n || input != static_cast<std::size_t>(t.index) % 3;
    const Json received = t.result_info.at("inputs");
    ASSERT_EQ(received.size(), 1u);
    EXPECT_EQ(received[0]["trial_index"], handed[input]["trial_index"]) << t.index;
    EXPECT_EQ(t.params, handed[input]["params"]) << t.index;
  }
  EXPECT_TRUE(not_mod_n) << "every trial's input happened to be index mod n: the test shows nothing";
}

TEST(HandOver, SpecErrorsNameTheJsonPathAndLeaveTheDatabaseUnchanged) {
  TempDir dir;
  submit(dir, campaign("ok", Json::array({probe_stage("explore", "random", 2)})));
  run(dir);  // settles the WAL into the main file
  const std::string before = file_bytes(dir / "podium.db");
  auto expect_error = [&](const Json& spec, const std::string& message) {
    podium::testing::write_file(dir / "bad.json", spec.dump());
    const auto r = run_podium({"submit", "bad.json"}, dir.path());
    EXPECT_EQ(r.exit_code, 2) << message;
    EXPECT_EQ(r.err, "podium: bad.json: " + message + "\n");
  };
  auto two_stages = [](const Json& inputs, const Json& second_config = Json::object()) {
    Json second = probe_stage("use", "random", 2, second_config);
    second["inputs"] = inputs;
    return campaign("bad", {probe_stage("explore", "random", 2, {{"features", 0}}), second});
  };
  expect_error(two_stages({{"stage", "nowhere"}}), "stages[1].inputs.stage: \"nowhere\" is not the name of an earlier stage");
  Json later = campaign("bad", {probe_stage("first", "random", 2), probe_stage("second", "random", 2)});
  later["stages"][0]["inputs"] = {{"stage", "second"}};
  expect_error(later, "stages[0].inputs.stage: \"second\" is a later stage (stages[1]); inputs come from earlier stages");
  expect_error(two_stages({{"stage", {"explore", "use"}}}),
               "stages[1].inputs.stage[1]: \"use\" is this stage itself; inputs come from earlier stages");
  expect_error(two_stages({{"stage", "explore"}, {"select", "best_per_strategy"}}),
               "stages[1].inputs.select: \"best_per_strategy\" needs strategy features, but stage \"explore\" (task probe) "
               "declares none");
  expect_error(two_stages({{"stage", "explore"}, {"select", "top"}}), "stages[1].inputs.k: missing (required)");
  expect_error(two_stages({{"stage", "explore"}, {"k", 2}}), "stages[1].inputs.k: 2 applies only to \"select\": \"top\"");
  expect_error(two_stages({{"stage", "explore"}, {"per_trial", "some"}}),
               "stages[1].inputs.per_trial: \"some\" is not one of all, each");
  Json no_inputs = campaign("bad", Json::array({probe_stage("explore", "novel_policy", 2)}));
  expect_error(no_inputs,
               "stages[0].search.algorithm: \"novel_policy\" seeks novel policies for an earlier stage's trials, "
               "but the stage has no \"inputs\"");
  Json per_input = campaign("bad", Json::array({probe_stage("explore", "random", {{"per_input", 2}})}));
  expect_error(per_input, "stages[0].budget.trials: {\"per_input\":2} needs the stage's \"inputs\"");
  EXPECT_EQ(file_bytes(dir / "podium.db"), before);
}

// A stage whose selection is empty at run time: the wall-time budget ends "explore" before it
// asks for any trial, so "each" has nothing to hand out.
TEST(HandOver, EachWithZeroInputsFailsTheStageAndTheCampaign) {
  TempDir dir;
  Json explore = probe_stage("explore", "random", 4);
  explore["budget"]["wall_time_s"] = 1e-9;
  Json each = probe_stage("each", "random", 2);
  each["inputs"] = {{"stage", "explore"}, {"select", "best"}, {"per_trial", "each"}};
  const auto id = submit(dir, campaign("empty", {explore, each}));
  run(dir, 1);
  auto s = open_store(dir);
  const std::string reason =
      "stages[1].inputs: per_trial \"each\" got 0 inputs (selecting \"best\" from stage \"explore\" gave none)";
  EXPECT_EQ(s->campaign(id)->state, "failed");
  EXPECT_EQ(s->campaign(id)->error, "stage \"each\" failed: " + reason);
  EXPECT_EQ(s->stages(id)[0].state, "done");
  EXPECT_EQ(s->stages(id)[1].state, "failed");
  EXPECT_EQ(s->stages(id)[1].error, reason);
  bool recorded = false;
  for (const auto& e : s->events(id)) recorded = recorded || (e["kind"] == "stage_failed" && e["payload"]["error"] == reason);
  EXPECT_TRUE(recorded);
  const auto status = run_podium({"status", std::to_string(id)}, dir.path());
  EXPECT_NE(status.out.find("error: stage \"each\" failed: " + reason), std::string::npos) << status.out;
}

// "Each strategy" from a stage where no trial succeeded (the landscape task failing on 90% of its
// box, every explore trial inside that part): no strategy, so nothing to hand over; the stage fails
// and says why, rather than handing on failed trials as if they were strategies.
TEST(HandOver, BestPerStrategyFromAStageWithoutSuccessFailsAndSaysWhy) {
  TempDir dir;
  Json explore = {{"name", "explore"},
                  {"task", "landscape"},
                  {"config", {{"fail_fraction", 0.9}}},
                  {"search", {{"algorithm", "random"}}},
                  {"budget", {{"trials", 3}}}};
  Json each = {{"name", "each"},
               {"task", "landscape"},
               {"search", {{"algorithm", "random"}}},
               {"budget", {{"trials", {{"per_input", 1}}}}},
               {"inputs", {{"stage", "explore"}, {"select", "best_per_strategy"}, {"per_trial", "each"}}}};
  const auto id = submit(dir, campaign("no-success", {explore, each}));
  run(dir, 1);
  auto s = open_store(dir);
  const auto trials = stage_trials(*s, id, 0);
  ASSERT_EQ(trials.size(), 3u);
  for (const auto& t : trials) {  // the fixture's premise: done, with features, and none a success
    ASSERT_EQ(t.state, "done");
    ASSERT_FALSE(t.result_info.at("success").get<bool>()) << t.params;
    EXPECT_FALSE(t.strategy.has_value());
  }
  const std::string reason =
      "stages[1].inputs: per_trial \"each\" got 0 inputs (selecting \"best_per_strategy\" from stage \"explore\" gave none; "
      "stage \"explore\" found no strategy in 3 done trials (none succeeded by its task's success rule "
      "{\"info\":\"/success\"}; a failed trial is no strategy))";
  EXPECT_EQ(s->campaign(id)->state, "failed");
  EXPECT_EQ(s->stages(id)[1].error, reason);
}

// The (trial, params, objectives, features, inputs received) of every trial of a campaign; the
// inputs by stage and trial index (their artifact paths name the campaign's own folder).
std::set<std::string> outcome(const Store& s, std::int64_t id) {
  std::set<std::string> out;
  for (const auto& st : s.stages(id))
    for (const auto& t : s.trials(st.id)) {
      Json inputs = Json::array();
      if (!t.result_info.is_null())
        for (const auto& in : t.result_info["inputs"]) inputs.push_back({in["stage"], in["trial_index"]});
      out.insert(Json{st.index, t.index, t.state, t.params, t.objectives, t.features, inputs}.dump());
    }
  return out;
}

bool stage_running(const TempDir& dir, std::int64_t id, int stage) {
  const auto r = run_podium({"status", std::to_string(id), "--json"}, dir.path());
  return r.exit_code == 0 && Json::parse(r.out)["stages"][stage]["state"] == "running";
}

TEST(HandOver, ResumeAfterSigkillHandsOverTheStoredInputs) {
  Json each = probe_stage("each", "random", {{"per_input", 3}}, {{"steps", 4}, {"sleep_s", 0.03}});
  each["inputs"] = {{"stage", "explore"}, {"select", "best_per_strategy"}, {"per_trial", "each"}};
  const Json spec = campaign("resume", {probe_stage("explore", "random", 8), each});
  TempDir reference;
  const auto ref_id = submit(reference, spec);
  run(reference);

  TempDir dir;
  const auto id = submit(dir, spec);
  int kills = 0;
  for (int round = 0; round < 6; ++round) {
    const pid_t pid = podium::testing::spawn_podium({"run"}, dir.path());
    podium::testing::wait_until(
        pid, [&] { return stage_running(dir, id, 1); }, 2.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    if (::waitpid(pid, nullptr, WNOHANG) != 0) break;  // it exited (-1: wait_until reaped it)
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    ++kills;
  }
  ASSERT_GE(kills, 2) << "the stage finished before two kills; make it longer";
  run(dir);

  auto s = open_store(dir);
  auto r = Store::open(reference / "podium.db", Store::Access::read_only);
  EXPECT_EQ(s->campaign(id)->state, "done");
  EXPECT_EQ(s->stages(id)[1].input_trials.value().size(), r->stages(ref_id)[1].input_trials.value().size());
  EXPECT_EQ(outcome(*s, id), outcome(*r, ref_id));
  int interrupted = 0;
  for (const auto& t : stage_trials(*s, id, 1)) {
    const auto attempts = s->attempts(t.id);
    for (const auto& a : attempts) interrupted += a.state == "interrupted";
    if (attempts.size() > 1) {  // the last attempt was told how the one before it ended
      const auto& previous = attempts[attempts.size() - 2];
      EXPECT_EQ(t.result_info["previous_attempt"],
                (Json{{"number", previous.number}, {"state", previous.state}, {"error", previous.error}}));
    }
    std::set<std::pair<std::string, double>> steps;
    for (const auto& m : s->metrics(t.id)) EXPECT_TRUE(steps.insert({m.name, m.step}).second) << "trial " << t.index;
    EXPECT_EQ(steps.size(), 4u) << "trial " << t.index;
  }
  EXPECT_GT(interrupted, 0) << "no attempt of the stage with inputs was running at a kill";
}

// The user guide's spec example, run as it is: "refine runs two trials for each strategy explore
// found, each given that strategy's best trial".
TEST(HandOver, UserGuideExampleDoesWhatItSays) {
  std::ifstream readme(std::filesystem::path(PODIUM_SOURCE_DIR) / "docs/user-guide.md");
  const std::string text{std::istreambuf_iterator<char>(readme), {}};
  const auto section = text.find("## The campaign spec");
  ASSERT_NE(section, std::string::npos);
  const auto begin = text.find("```json\n", section) + 8, end = text.find("```", begin);
  const Json spec = Json::parse(text.substr(begin, end - begin));
  TempDir dir;
  const auto id = submit(dir, spec);
  run(dir);
  auto s = open_store(dir);
  ASSERT_EQ(s->campaign(id)->state, "done");
  std::map<std::int64_t, const store::TrialRecord*> best_of_strategy;
  const auto explore = stage_trials(*s, id, 0);
  for (const auto& t : explore)
    if (t.state == "done" && (!best_of_strategy.count(*t.strategy) || objective(t) > objective(*best_of_strategy[*t.strategy])))
      best_of_strategy[*t.strategy] = &t;
  ASSERT_GE(best_of_strategy.size(), 2u);
  const auto refine = s->stages(id)[1];
  const Json handed = refine.input_trials.value();
  ASSERT_EQ(handed.size(), best_of_strategy.size());
  std::size_t i = 0;
  for (const auto& [strategy, t] : best_of_strategy) {
    EXPECT_EQ(handed[i]["trial_index"], t->index);
    EXPECT_EQ(handed[i]["strategy"], strategy);
    EXPECT_EQ(handed[i]["params"], t->params);
    ++i;
  }
  const auto trials = stage_trials(*s, id, 1);
  EXPECT_EQ(trials.size(), 2 * handed.size());
  for (const auto& t : trials) {
    EXPECT_EQ(t.state, "done");
    EXPECT_EQ(t.info.at("input"), t.index % handed.size());  // RunRequest::inputs = {handed[input]}
  }
}

// The thesis's two-stage pipeline, as shipped in campaigns/: BDS, then novel-policy seeking from
// the best trial of each strategy BDS found.
TEST(HandOver, BdsThenNovelPolicyLandscapeCampaignSubmitsAndRuns) {
  TempDir dir;
  const auto id =
      submit(dir, base::read_json_file(std::filesystem::path(PODIUM_SOURCE_DIR) / "campaigns/landscape_bds_novel_policy.json"));
  run(dir);
  auto s = open_store(dir);
  ASSERT_EQ(s->campaign(id)->state, "done") << s->campaign(id)->error;
  const Json handed = s->stages(id)[1].input_trials.value();
  ASSERT_GE(handed.size(), 2u);
  const auto trials = stage_trials(*s, id, 1);
  ASSERT_EQ(trials.size(), 3 * handed.size());
  std::map<std::size_t, int> per_input;
  for (const auto& t : trials) {
    EXPECT_EQ(t.state, "done");
    const auto input = t.info.at("input").get<std::size_t>();
    ++per_input[input];
    EXPECT_EQ(t.params, handed[input]["params"]);  // novel-policy seeking runs at its input's parameters
    EXPECT_EQ(t.context.at("warm_start"), handed[input]["artifacts"]["result"]);
    EXPECT_GE(t.context.at("novelty").at("features").size(), 1u);
  }
  for (const auto& [input, n] : per_input) EXPECT_EQ(n, 3) << "input " << input;
}

}  // namespace
}  // namespace podium::orchestrator
