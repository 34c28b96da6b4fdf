// The test_pendulum task (PPO on learn's Pendulum): the conformance suite, and a warm start whose
// first evaluation is its source policy's last.
#include <gtest/gtest.h>

#include "podium/base/json.h"
#include "process.h"
#include "task_conformance.h"

namespace podium::tests::pendulum {
namespace {

using base::Json;
namespace fs = std::filesystem;

PODIUM_TASK_CONFORMANCE(TestPendulum, {.task = "test_pendulum", .long_config = {{"updates", 100000}},
                                       .resume_config = {{"updates", 60}, {"checkpoint_every", 3}},
                                       .kill_after_metric_points = 12, .resumes_from_checkpoint = true,
                                       .artifacts = {"policy"}});

// `podium trial --batch` on one order in `dir`; returns result.json.
Json run_trial(const fs::path& dir, const Json& inputs, double log10_lr) {
  fs::create_directories(dir);
  const Json order = {{"key", 1}, {"task", "test_pendulum"}, {"config", {{"updates", 4}}},
                      {"params", {{"log10_lr", log10_lr}}}, {"context", Json::object()}, {"inputs", inputs},
                      {"previous_attempt", nullptr}, {"seed", 5}, {"trial_index", 0}, {"attempt", 1},
                      {"work_dir", (dir / "trial").string()}};
  podium::testing::write_file(dir / "order.json", order.dump());
  podium::testing::write_file(dir / "batch.txt", (dir / "order.json").string() + "\n");
  const auto r = podium::testing::run_podium({"trial", "--batch", (dir / "batch.txt").string()}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return base::read_json_file(dir / "result.json");
}

TEST(TestPendulumTask, WarmStartsFromItsInputsPolicy) {
  podium::testing::TempDir dir;
  const Json source = run_trial(dir / "source", Json::array(), -2.5);
  ASSERT_EQ(source["type"], "result") << source;
  const Json input = {{"stage", "explore"}, {"stage_index", 0}, {"trial_index", 3}, {"params", {{"log10_lr", -2.5}}},
                      {"objectives", source["objectives"]}, {"features", source["features"]}, {"strategy", 0},
                      {"artifacts", {{"policy", source["artifacts"][0]["path"]}}}};
  const Json warm = run_trial(dir / "warm", Json::array({input}), -3.0);
  ASSERT_EQ(warm["type"], "result") << warm;
  EXPECT_NEAR(warm["info"]["first_eval_return"].get<double>(), source["objectives"][0].get<double>(), 1e-9);
  EXPECT_EQ(warm["info"]["warm_start"], (Json{{"stage", "explore"}, {"trial_index", 3}}));
  const Json cold = run_trial(dir / "cold", Json::array(), -3.0);
  EXPECT_NE(cold["info"]["first_eval_return"], warm["info"]["first_eval_return"]);
}

}  // namespace
}  // namespace podium::tests::pendulum
