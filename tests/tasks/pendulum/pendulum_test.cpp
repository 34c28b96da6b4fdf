// The test_pendulum task (PPO on learn's Pendulum): the conformance suite, and a warm start whose
// first evaluation is its source policy's last.
#include <gtest/gtest.h>

#include "batch_trial.h"
#include "podium/base/json.h"
#include "task_conformance.h"

namespace podium::tests::pendulum {
namespace {

using base::Json;
namespace fs = std::filesystem;

// The warm start: from the smoke trial's policy, handed over as an input trial.
podium::testing::WarmStartCase::Order from_policy(const fs::path& source, const Json& result) {
  const Json input = podium::testing::input_from_smoke(source, result);
  return {{{"updates", 60}, {"checkpoint_every", 3}}, Json::array({input})};
}
PODIUM_TASK_CONFORMANCE(TestPendulum, {.task = "test_pendulum",
                                       .long_config = {{"updates", 100000}},
                                       .resume_config = {{"updates", 60}, {"checkpoint_every", 3}},
                                       // Whole updates past the first checkpoint (update 3), so the
                                       // kill cannot race its write: the test before training sends 5
                                       // points, each update 5 or 6 (eval_return, four time/, train_return
                                       // when an episode ended), so point 72 comes after update 9's
                                       // checkpoint was written, and long before the 60th update.
                                       .kill_after_metric_points = 72,
                                       .resumes_from_checkpoint = true,
                                       .artifacts = {"policy"},
                                       .warm_start = podium::testing::WarmStartCase{from_policy, 40}});

// `podium trial --batch` on one order in `dir`; returns result.json.
Json run_trial(const fs::path& dir, const Json& inputs, double log10_lr) {
  const auto run = podium::testing::run_batch_trial(podium::testing::order_json({.task = "test_pendulum",
                                                                                 .config = {{"updates", 4}},
                                                                                 .params = {{"log10_lr", log10_lr}},
                                                                                 .inputs = inputs,
                                                                                 .seed = 5,
                                                                                 .work_dir = dir / "trial"}),
                                                    dir);
  EXPECT_EQ(run.run.exit_code, 0) << run.run.err;
  return run.result;
}

TEST(TestPendulumTask, WarmStartsFromItsInputsPolicy) {
  podium::testing::TempDir dir;
  const Json source = run_trial(dir / "source", Json::array(), -2.5);
  ASSERT_EQ(source["type"], "result") << source;
  const Json input = {{"stage", "explore"},
                      {"stage_index", 0},
                      {"trial_index", 3},
                      {"params", {{"log10_lr", -2.5}}},
                      {"objectives", source["objectives"]},
                      {"features", source["features"]},
                      {"strategy", 0},
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
