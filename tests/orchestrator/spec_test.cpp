#include "podium/orchestrator/spec.h"

#include <gtest/gtest.h>

#include <functional>

#include "podium/base/error.h"

namespace podium::orchestrator {
namespace {

Json valid_spec() {
  return Json::parse(R"({
    "name": "demo", "seed": 3,
    "stages": [{"name": "a", "task": "landscape", "search": {"algorithm": "random"}, "budget": {"trials": 10}},
               {"name": "b", "task": "landscape", "search": {"algorithm": "random"}, "budget": {"trials": 5},
                "inputs": {"stage": "a", "select": "best"}}]})");
}

std::string error_of(const Json& spec) {
  try {
    parse_spec(spec, "spec.json");
  } catch (const base::UserError& e) {
    return e.what();
  }
  return "";
}

TEST(CampaignSpec, ParsesDefaults) {
  const auto spec = parse_spec(valid_spec(), "spec.json");
  EXPECT_EQ(spec.name, "demo");
  EXPECT_EQ(spec.workers, 2);
  EXPECT_EQ(spec.retries, 2);
  EXPECT_EQ(spec.stages.size(), 2u);
  ASSERT_TRUE(spec.stages[1].inputs.has_value());
  EXPECT_EQ(spec.stages[1].inputs->stages, std::vector<std::string>{"a"});
  EXPECT_EQ(spec.stages[1].inputs->select, "best");
  EXPECT_EQ(spec.stages[1].inputs->per_trial, "all");
  EXPECT_FALSE(spec.stages[0].inputs.has_value());
}

TEST(CampaignSpec, ParsesInputsFromSeveralStagesAndABudgetPerInput) {
  auto j = valid_spec();
  j["stages"].push_back(Json::parse(R"({"name": "c", "task": "landscape", "search": {"algorithm": "random"},
      "budget": {"trials": {"per_input": 3}},
      "inputs": {"stage": ["b", "a"], "select": "top", "k": 2, "per_trial": "each"}})"));
  const auto spec = parse_spec(j, "spec.json");
  const auto& c = spec.stages[2];
  EXPECT_EQ(c.inputs->stages, (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(c.inputs->top_k, 2);
  EXPECT_EQ(c.budget_per_input, 3);
  EXPECT_EQ(c.budget_trials, 0);  // set when the stage starts
  EXPECT_EQ(to_json(*c.inputs), Json::parse(R"({"stages": ["b", "a"], "select": "top", "k": 2, "per_trial": "each"})"));
}

TEST(CampaignSpec, ErrorsNameTheJsonPath) {
  auto j = valid_spec();
  j["stages"][1]["budget"]["trials"] = -3;
  EXPECT_EQ(error_of(j), "spec.json: stages[1].budget.trials: -3 is not in [1, 10000000]");

  j = valid_spec();
  j["stages"][0]["search"]["algoritm"] = "bds";
  EXPECT_EQ(error_of(j),
            "spec.json: stages[0].search.algoritm: unknown key (known: algorithm, config) (did you mean algorithm?)");

  j = valid_spec();
  j["seed"] = "seven";
  EXPECT_EQ(error_of(j), "spec.json: seed: \"seven\" is not an integer");

  j = valid_spec();
  j["workers"] = 0;
  EXPECT_EQ(error_of(j), "spec.json: workers: 0 is not in [1, 1024]");

  j = valid_spec();

  j = valid_spec();
  j["stages"][1]["inputs"]["stage"] = "b";
  EXPECT_EQ(error_of(j), "spec.json: stages[1].inputs.stage: \"b\" is this stage itself; inputs come from earlier stages");

  j = valid_spec();
  j["stages"][1]["inputs"]["stage"] = "z";
  EXPECT_EQ(error_of(j), "spec.json: stages[1].inputs.stage: \"z\" is not the name of an earlier stage");

  j = valid_spec();
  j["stages"][0]["inputs"] = {{"stage", "b"}};
  EXPECT_EQ(error_of(j),
            "spec.json: stages[0].inputs.stage: \"b\" is a later stage (stages[1]); inputs come from earlier stages");

  j = valid_spec();
  j["stages"][1]["inputs"]["stage"] = {"a", "a"};
  EXPECT_EQ(error_of(j), "spec.json: stages[1].inputs.stage[1]: \"a\" is named twice");

  j = valid_spec();
  j["stages"][1]["inputs"]["select"] = "worst";
  EXPECT_EQ(error_of(j), "spec.json: stages[1].inputs.select: \"worst\" is not one of all, best, best_per_strategy, top");

  j = valid_spec();
  j["stages"][1]["inputs"]["select"] = "top";
  j["stages"][1]["inputs"]["k"] = 0;
  EXPECT_EQ(error_of(j), "spec.json: stages[1].inputs.k: 0 is not in [1, 1000000]");

  j = valid_spec();
  j["stages"][1]["budget"]["trials"] = {{"per_input", 0}};
  EXPECT_EQ(error_of(j), "spec.json: stages[1].budget.trials.per_input: 0 is not in [1, 1000000]");

  j = valid_spec();
  j["stages"][0]["budget"]["trials"] = {{"per_input", 2}};
  EXPECT_EQ(error_of(j), "spec.json: stages[0].budget.trials: {\"per_input\":2} needs the stage's \"inputs\"");

  j = valid_spec();
  j.erase("name");
  EXPECT_EQ(error_of(j), "spec.json: name: missing (required)");

  j = valid_spec();
  j["executor"] = {{"kind", "kubernetes"}};
  EXPECT_EQ(error_of(j), "spec.json: executor.kind: \"kubernetes\" is not one of local, slurm");

  j = valid_spec();
  j["trial_timeout_s"] = 0;
  EXPECT_EQ(error_of(j), "spec.json: trial_timeout_s: 0 is not in (0, 31536000]");

  j = valid_spec();
  j["stages"] = Json::array();
  EXPECT_EQ(error_of(j), "spec.json: stages: [] is not a non-empty array");

  j = valid_spec();
  j["stages"][0]["config"] = "dim=3";
  EXPECT_EQ(error_of(j), "spec.json: stages[0].config: \"dim=3\" is not an object");

  j = valid_spec();
  j["stages"][1]["name"] = "a";
  EXPECT_EQ(error_of(j), "spec.json: stages[1].name: \"a\" is already the name of an earlier stage");
}

// Every number of the spec has a range (README "The campaign spec"), checked
// at submit: nothing is cut to 32 bits or overflows later (a trial_timeout_s of 1e10 s overflowed
// steady_clock and timed every trial out at once).
TEST(CampaignSpec, EveryNumberIsCheckedAgainstItsDocumentedRange) {
  const std::vector<std::pair<std::function<void(Json&)>, std::string>> cases = {
      {[](Json& j) { j["trial_timeout_s"] = 9.3e9; }, "trial_timeout_s: 9300000000.0 is not in (0, 31536000]"},
      {[](Json& j) { j["workers"] = 1000000000000; }, "workers: 1000000000000 is not in [1, 1024]"},
      {[](Json& j) { j["workers"] = 4294967297; }, "workers: 4294967297 is not in [1, 1024]"},
      {[](Json& j) { j["workers"] = 1025; }, "workers: 1025 is not in [1, 1024]"},
      {[](Json& j) { j["retries"] = 4294967296; }, "retries: 4294967296 is not in [0, 100]"},
      {[](Json& j) { j["seed"] = -1; }, "seed: -1 is not >= 0"},
      {[](Json& j) { j["seed"] = 18446744073709551615u; }, "seed: 18446744073709551615 is not in [0, 9223372036854775807]"},
      {[](Json& j) { j["stages"][0]["budget"]["trials"] = 10000001; },
       "stages[0].budget.trials: 10000001 is not in [1, 10000000]"},
      {[](Json& j) { j["stages"][0]["budget"]["wall_time_s"] = 1e12; },
       "stages[0].budget.wall_time_s: 1000000000000.0 is not in (0, 31536000]"},
      {[](Json& j) {
         j["stages"][1]["budget"]["trials"] = {{"per_input", 4294967296}};
       },
       "stages[1].budget.trials.per_input: 4294967296 is not in [1, 1000000]"},
      {[](Json& j) { j["stages"][0]["strategy_threshold"] = -0.5; }, "stages[0].strategy_threshold: -0.5 is not > 0"},
      {[](Json& j) {
         j["stages"][1]["inputs"] = {{"stage", "a"}, {"select", "top"}, {"k", 1e6 + 1}};
       },
       "stages[1].inputs.k: 1000001.0 is not an integer"},
      {[](Json& j) {
         j["executor"] = {{"kind", "slurm"}, {"partition", "p"}, {"cpus_per_task", 2000}};
       },
       "executor.cpus_per_task: 2000 is not in [1, 1024]"},
      {[](Json& j) {
         j["executor"] = {{"kind", "slurm"}, {"partition", "p"}, {"max_jobs_in_queue", 0}};
       },
       "executor.max_jobs_in_queue: 0 is not in [1, 100000]"},
  };
  for (const auto& [edit, error] : cases) {
    auto j = valid_spec();
    edit(j);
    EXPECT_EQ(error_of(j), "spec.json: " + error) << j.dump();
  }
  // The ends of each range are accepted.
  auto j = valid_spec();
  j["workers"] = 1024;
  j["retries"] = 100;
  j["trial_timeout_s"] = 31536000;
  j["seed"] = 9223372036854775807;
  j["stages"][0]["budget"] = {{"trials", 10000000}, {"wall_time_s", 31536000}};
  const auto spec = parse_spec(j, "spec.json");
  EXPECT_EQ(spec.workers, 1024);
  EXPECT_EQ(spec.seed, 9223372036854775807u);
  EXPECT_EQ(spec.stages[0].budget_trials, 10000000);
}

// Names are printed by status and looked up by name, so control characters
// (a terminal escape, a NUL that made a campaign unfindable) are refused with the JSON path.
TEST(CampaignSpec, NamesWithControlCharactersAreRefused) {
  for (const std::string& bad : {std::string("a\0b", 3), std::string("red\x1b[31m"), std::string("two\nlines"),
                                 std::string("del\x7f"), std::string("c1\xc2\x9b")}) {
    auto j = valid_spec();
    j["name"] = bad;
    EXPECT_EQ(error_of(j), "spec.json: name: " + Json(bad).dump() + " has a control character (names are printed and typed)");
    j = valid_spec();
    j["stages"][0]["name"] = bad;
    EXPECT_EQ(error_of(j),
              "spec.json: stages[0].name: " + Json(bad).dump() + " has a control character (names are printed and typed)");
  }
  auto j = valid_spec();
  j["name"] = "démo ✓ 2026";  // printable UTF-8 is a name
  EXPECT_EQ(parse_spec(j, "spec.json").name, "démo ✓ 2026");
}

TEST(CampaignSpec, ParsesASlurmExecutorAndNamesItsErrors) {
  auto j = valid_spec();
  j["executor"] = Json::parse(R"({"kind": "slurm", "partition": "cpu", "time": "01:00:00", "cpus_per_task": 2,
                                  "extra_sbatch": ["--qos=low"]})");
  const auto x = parse_spec(j, "spec.json").executor;
  EXPECT_EQ(x.partition, "cpu");
  EXPECT_EQ(x.time, "01:00:00");
  EXPECT_EQ(x.cpus_per_task, 2);
  EXPECT_EQ(x.extra_sbatch, std::vector<std::string>{"--qos=low"});
  EXPECT_EQ(x.max_jobs_in_queue, 100);

  j["executor"]["time"] = "1 hour";
  EXPECT_EQ(error_of(j),
            "spec.json: executor.time: \"1 hour\" is not a Slurm time limit (minutes, or "
            "[days-]hours:minutes:seconds)");
  j["executor"]["time"] = "30";
  j["executor"]["extra_sbatch"] = {"--qos=low", 7};
  EXPECT_EQ(error_of(j), "spec.json: executor.extra_sbatch[1]: 7 is not a string");
  j["executor"] = {{"kind", "local"}, {"partition", "cpu"}};
  EXPECT_EQ(error_of(j), "spec.json: executor.partition: unknown key (known: kind)");
}

}  // namespace
}  // namespace podium::orchestrator
