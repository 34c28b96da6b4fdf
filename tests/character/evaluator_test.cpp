// The fixed-starts evaluator: measures, success rate, and trajectories the replay accepts.
#include "podium/character/evaluator.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "podium/base/error.h"
#include "env_util.h"

namespace podium::character {
namespace {

namespace fs = std::filesystem;

EvaluationConfig config_for(const fs::path& dir) {
  EvaluationConfig c;
  c.start_seeds = {101, 102, 103};
  c.measures.push_back({"final_head_height_m", [](const CharacterEnv& env) { return env.features().head_height_m; }});
  c.success = [](const CharacterEnv& env) { return env.features().head_height_m > 0.3; };
  c.record = {1};
  c.record_dir = dir;
  return c;
}

const PolicyFn kLimp = [](std::span<const double>, std::span<double> action) { std::fill(action.begin(), action.end(), 0.0); };

TEST(Evaluator, FixedStartsGiveTheSameReportTwice) {
  const fs::path dir = fs::temp_directory_path() / "podium_character_eval";
  fs::remove_all(dir);
  CharacterEnv env(testing::getup_like_parts(8));
  const EvaluationReport first = evaluate(env, kLimp, config_for(dir));
  env.seed(999);  // whatever ran before, the starts are the seeds'
  std::vector<double> obs;
  env.reset(obs);
  const EvaluationReport second = evaluate(env, kLimp, config_for(dir));
  ASSERT_EQ(first.returns.size(), 3u);
  EXPECT_EQ(first.returns, second.returns);
  EXPECT_EQ(first.measures.at("final_head_height_m"), second.measures.at("final_head_height_m"));
  double mean = 0, rate = 0, head = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    mean += first.returns[i] / 3;
    head += first.measures.at("final_head_height_m")[i] / 3;
    rate += (first.measures.at("final_head_height_m")[i] > 0.3) / 3.0;
    EXPECT_GT(first.returns[i], 0.0);  // reward = head height, 8 steps
  }
  EXPECT_DOUBLE_EQ(first.mean_return, mean);
  EXPECT_DOUBLE_EQ(first.success_rate, rate);
  EXPECT_DOUBLE_EQ(first.mean("final_head_height_m"), head);
  EXPECT_NE(first.returns[0], first.returns[1]);  // different falls
  const base::Json j = first.to_json();
  EXPECT_EQ(j["measures"]["final_head_height_m"].size(), 3u);
  fs::remove_all(dir);
}

// The file follows sim/README.md's trajectory format as web_dashboard/static/replay.js reads it:
// a header line with format "podium-trajectory" and links with shapes, then one frame per line
// with t and one 7-number pose per link.
TEST(Evaluator, RecordedRolloutIsATrajectoryTheReplayAccepts) {
  const fs::path dir = fs::temp_directory_path() / "podium_character_eval_traj";
  fs::remove_all(dir);
  CharacterEnv env(testing::getup_like_parts(8));
  const EvaluationReport report = evaluate(env, kLimp, config_for(dir));
  ASSERT_EQ(report.trajectories.size(), 1u);
  EXPECT_EQ(report.trajectories[0], dir / "trajectory_1.jsonl");
  std::ifstream in(report.trajectories[0]);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const base::Json header = base::Json::parse(line);
  EXPECT_EQ(header["format"], "podium-trajectory");
  const std::size_t links = env.model().links().size();
  ASSERT_EQ(header["links"].size(), links);
  std::size_t shapes = 0;
  for (const auto& l : header["links"]) shapes += l["shapes"].size();
  EXPECT_GT(shapes, 10u);
  std::size_t frames = 0;
  double last_t = -1;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const base::Json f = base::Json::parse(line);
    ASSERT_TRUE(f["t"].is_number());
    EXPECT_GT(f["t"].get<double>(), last_t);
    last_t = f["t"].get<double>();
    ASSERT_EQ(f["links"].size(), links);
    for (const auto& pose : f["links"]) ASSERT_EQ(pose.size(), 7u);
    ++frames;
  }
  EXPECT_EQ(frames, 9u);  // the start state and 8 control steps
  fs::remove_all(dir);
}

TEST(Evaluator, RejectsARecordIndexOutsideTheStarts) {
  CharacterEnv env(testing::getup_like_parts(3));
  EvaluationConfig c = config_for(fs::temp_directory_path());
  c.record = {7};
  EXPECT_THROW(evaluate(env, kLimp, c), base::UserError);
}

}  // namespace
}  // namespace podium::character
