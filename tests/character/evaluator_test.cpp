// The fixed-starts evaluator: measures, success rate, and trajectories the replay accepts.
#include "podium/character/evaluator.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "env_util.h"
#include "podium/base/error.h"
#include "podium/sim/world.h"

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

std::vector<std::string> lines_of(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

// record_min_hz: the World's own states between control steps (800 Hz simulation, 40 Hz control:
// every 5th simulation step for ≥ 100 Hz, 160 Hz), the control steps' frames among them as they
// were, and the evaluation's numbers unchanged.
TEST(Evaluator, DenseRecordingTakesSimulationStatesAndChangesNothingElse) {
  const fs::path sparse_dir = fs::temp_directory_path() / "podium_character_eval_sparse";
  const fs::path dense_dir = fs::temp_directory_path() / "podium_character_eval_dense";
  fs::remove_all(sparse_dir);
  fs::remove_all(dense_dir);
  CharacterEnv env(testing::getup_like_parts(8));
  ASSERT_EQ(env.world().substeps(), 20);
  const EvaluationReport sparse = evaluate(env, kLimp, config_for(sparse_dir));
  EvaluationConfig c = config_for(dense_dir);
  c.record_min_hz = 100.0;
  const EvaluationReport dense = evaluate(env, kLimp, c);
  EXPECT_EQ(dense.returns, sparse.returns);
  EXPECT_EQ(dense.successes, sparse.successes);
  EXPECT_EQ(dense.measures, sparse.measures);

  const std::vector<std::string> few = lines_of(sparse.trajectories.at(0)), many = lines_of(dense.trajectories.at(0));
  ASSERT_EQ(few.size(), 1u + 9u);
  ASSERT_EQ(many.size(), 1u + 8u * 4u + 1u);  // the start, then 4 frames per control step
  EXPECT_EQ(many[0], few[0]);                 // the same header
  for (std::size_t f = 0; f < 9; ++f) EXPECT_EQ(many[1 + 4 * f], few[1 + f]) << "control step " << f;
  const double t0 = base::Json::parse(many[1])["t"].get<double>();
  for (std::size_t f = 1; f + 1 < many.size(); ++f)
    EXPECT_NEAR(base::Json::parse(many[1 + f])["t"].get<double>() - t0, static_cast<double>(f) / 160.0, 1e-5);
  // The states are the simulation's: consecutive frames differ (no repeated or held frames).
  for (std::size_t f = 2; f < many.size(); ++f) EXPECT_NE(base::Json::parse(many[f])["q"], base::Json::parse(many[f - 1])["q"]);
  fs::remove_all(sparse_dir);
  fs::remove_all(dense_dir);
}

// A task's own observer (the sprint's finish line) sees every simulation step of every episode,
// recorded densely or not, and is the world's observer again afterwards.
TEST(Evaluator, KeepsTheWorldsOwnSubstepObserverThroughEveryEpisode) {
  const fs::path dir = fs::temp_directory_path() / "podium_character_eval_observer";
  fs::remove_all(dir);
  CharacterEnv env(testing::getup_like_parts(8));
  int seen = 0;
  env.world().set_substep_observer([&seen](sim::World&) { ++seen; });
  EvaluationConfig c = config_for(dir);
  c.record.clear();
  ASSERT_EQ(evaluate(env, kLimp, c).returns.size(), 3u);
  const int plain = seen;  // the resets' falls and three episodes of 8 control steps
  EXPECT_GE(plain, 3 * 8 * env.world().substeps());
  seen = 0;
  c = config_for(dir);
  c.record_min_hz = 100.0;  // episode 1 recorded between control steps, beside the world's observer
  evaluate(env, kLimp, c);
  EXPECT_EQ(seen, plain);
  ASSERT_TRUE(env.world().substep_observer());
  env.world().substep_observer()(env.world());
  EXPECT_EQ(seen, plain + 1);
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
