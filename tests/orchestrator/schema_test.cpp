// The JSON Schema in campaigns/ and the C++ validator must agree: every shipped spec passes both,
// and each kind of violation is rejected by both (schema checked with python3-jsonschema); and
// every shipped spec submits through the real CLI.
#include <gtest/gtest.h>

#include "podium/base/error.h"
#include "podium/orchestrator/spec.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

namespace fs = std::filesystem;
using base::Json;

const fs::path kSource = PODIUM_SOURCE_DIR;

std::string run_schema_check(const std::vector<fs::path>& files) {
  std::string command = "/usr/bin/python3 " + (kSource / "tests/orchestrator/schema_check.py").string() + " " +
                        (kSource / "campaigns/campaign.schema.json").string();
  for (const auto& f : files) command += " " + f.string();
  return podium::testing::shell(command).out;
}

TEST(CampaignSchema, ShippedSpecsPassSchemaAndValidator) {
  std::vector<fs::path> specs;
  for (const auto& entry : fs::directory_iterator(kSource / "campaigns"))
    if (entry.path().extension() == ".json" && entry.path().filename() != "campaign.schema.json") specs.push_back(entry.path());
  ASSERT_FALSE(specs.empty());
  const std::string out = run_schema_check(specs);
  for (const auto& spec : specs) {
    EXPECT_NE(out.find(spec.string() + " valid"), std::string::npos) << out;
    EXPECT_NO_THROW(parse_spec(base::read_json_file(spec), spec.string())) << spec;
  }
}

// The tasks check each stage's resolved config (defaults, preset, spec) at submit: every shipped
// spec is accepted by its plugins, as a user would submit it.
TEST(CampaignSchema, ShippedSpecsAreAcceptedByTheirTasks) {
  podium::testing::TempDir dir;
  for (const auto& entry : fs::directory_iterator(kSource / "campaigns")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "campaign.schema.json") continue;
    const auto run = podium::testing::run_podium({"submit", entry.path().string()}, dir.path());
    EXPECT_EQ(run.exit_code, 0) << entry.path() << ": " << run.err;
  }
}

TEST(CampaignSchema, ViolationsAreRejectedByBoth) {
  const Json valid = base::read_json_file(kSource / "campaigns/landscape_smoke.json");
  std::vector<Json> bad;
  auto with = [&](auto&& edit) {
    Json j = valid;
    edit(j);
    bad.push_back(j);
  };
  with([](Json& j) { j["surprise"] = 1; });
  with([](Json& j) { j["seed"] = -1; });
  with([](Json& j) { j["workers"] = 0; });
  with([](Json& j) { j["stages"][0]["budget"]["trials"] = 0; });
  with([](Json& j) { j["stages"][0]["search"].erase("algorithm"); });
  with([](Json& j) { j["stages"][0]["inputs"] = {{"stage", "explore"}, {"select", "worst"}}; });
  with([](Json& j) { j["stages"][0]["inputs"] = {{"stage", "explore"}, {"select", "top"}}; });
  with([](Json& j) { j["stages"][0]["inputs"] = {{"stage", "explore"}, {"per_trial", "some"}}; });
  with([](Json& j) { j["stages"][0]["budget"]["trials"] = {{"per_input", 0}}; });
  with([](Json& j) { j["executor"] = {{"kind", "cloud"}}; });
  with([](Json& j) { j["stages"] = Json::array(); });
  // The documented ranges and names without control characters.
  with([](Json& j) { j["workers"] = 1025; });
  with([](Json& j) { j["retries"] = 101; });
  with([](Json& j) { j["trial_timeout_s"] = 1e10; });
  with([](Json& j) { j["seed"] = 9223372036854775808u; });
  with([](Json& j) { j["stages"][0]["budget"]["trials"] = 10000001; });
  with([](Json& j) { j["stages"][0]["budget"]["wall_time_s"] = 31536001; });
  with([](Json& j) { j["name"] = std::string("a\0b", 3); });
  with([](Json& j) { j["stages"][0]["name"] = "x\n"; });
  podium::testing::TempDir dir;
  std::vector<fs::path> files;
  for (std::size_t i = 0; i < bad.size(); ++i) {
    files.push_back(dir / ("bad" + std::to_string(i) + ".json"));
    podium::testing::write_file(files.back(), bad[i].dump());
    EXPECT_THROW(parse_spec(bad[i], "bad"), base::UserError) << bad[i].dump();
  }
  const std::string out = run_schema_check(files);
  for (const auto& f : files) EXPECT_NE(out.find(f.string() + " invalid"), std::string::npos) << out;
}

}  // namespace
}  // namespace podium::orchestrator
