#include "podium/orchestrator/spec.h"

#include <gtest/gtest.h>

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
  EXPECT_EQ(spec.stages[1].inputs["select"], "best");
}

TEST(CampaignSpec, ErrorsNameTheJsonPath) {
  auto j = valid_spec();
  j["stages"][1]["budget"]["trials"] = -3;
  EXPECT_EQ(error_of(j), "spec.json: stages[1].budget.trials: -3 is not >= 1");

  j = valid_spec();
  j["stages"][0]["search"]["algoritm"] = "bds";
  EXPECT_EQ(error_of(j), "spec.json: stages[0].search.algoritm: unknown key");

  j = valid_spec();
  j["seed"] = "seven";
  EXPECT_EQ(error_of(j), "spec.json: seed: \"seven\" is not an integer");

  j = valid_spec();
  j["workers"] = 0;
  EXPECT_EQ(error_of(j), "spec.json: workers: 0 is not >= 1");

  j = valid_spec();
  j["stages"][1]["inputs"]["stage"] = "b";
  EXPECT_EQ(error_of(j), "spec.json: stages[1].inputs.stage: \"b\" is not the name of an earlier stage");

  j = valid_spec();
  j.erase("name");
  EXPECT_EQ(error_of(j), "spec.json: name: missing (required)");

  j = valid_spec();
  j["executor"] = {{"kind", "kubernetes"}};
  EXPECT_EQ(error_of(j), "spec.json: executor.kind: \"kubernetes\" is not a supported executor (supported: \"local\", \"slurm\")");

  j = valid_spec();
  j["trial_timeout_s"] = 0;
  EXPECT_EQ(error_of(j), "spec.json: trial_timeout_s: 0 is not > 0");

  j = valid_spec();
  j["stages"] = Json::array();
  EXPECT_EQ(error_of(j), "spec.json: stages: [] is not a non-empty array");
}

}  // namespace
}  // namespace podium::orchestrator
