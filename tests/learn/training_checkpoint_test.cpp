// TrainingCheckpoint: a run stopped after k updates and resumed by a fresh learner from its last
// checkpoint ends with bitwise the uninterrupted run's parameters and the same per-update stats,
// and its resume sends again exactly the metric points the checkpoint covers.
#include "podium/learn/training_checkpoint.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "podium/base/error.h"
#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

namespace podium::learn {
namespace {

namespace fs = std::filesystem;

struct Stats {
  std::int64_t env_steps;
  std::size_t episodes;
  double mean_return;
  bool operator==(const Stats& o) const {
    return env_steps == o.env_steps && episodes == o.episodes &&
           (mean_return == o.mean_return || (std::isnan(mean_return) && std::isnan(o.mean_return)));
  }
};

struct Stop {};  // thrown from the callback: the "kill"

std::unique_ptr<Learner> make(const std::string& algorithm) {
  Pendulum probe;
  if (algorithm == "ppo") {
    PpoConfig c;
    c.rollout_steps = 40;  // 120-step iterations, not aligned with the 200-step episodes
    c.minibatch_size = 30;
    c.epochs = 2;
    c.sigma_anneal_steps = c.lr_anneal_steps = 1500;
    c.policy_lr_end = 1e-4;
    return std::make_unique<Ppo>(c, probe.observation_space(), probe.action_space(), 5);
  }
  SacConfig c;
  c.warmup_steps = 150;
  c.batch_size = 32;
  c.buffer_capacity = 500;  // wraps around before the end
  c.updates_per_step = 0.5;
  c.log_interval_steps = 90;
  c.normalize_observations = true;
  return std::make_unique<Sac>(c, probe.observation_space(), probe.action_space(), 5);
}

VecEnv pendulums() {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < 3; ++i) envs.push_back(std::make_unique<Pendulum>());
  return VecEnv(std::move(envs), 2, 17);
}

struct Run {
  std::vector<Stats> stats;  // as reported, one per update, duplicates after a resume dropped
  std::vector<float> parameters;
};

// Trains to `total` steps with a checkpoint every 2 updates; throws Stop after `stop_after`
// updates of this attempt (0: never). Reports each update once, using the extra state.
void attempt(const std::string& algorithm, const fs::path& file, std::int64_t total, int stop_after, Run& run) {
  auto learner = make(algorithm);
  auto envs = pendulums();
  TrainingCheckpoint checkpoint(file, 2);
  std::size_t reported = 0;
  if (auto extra = checkpoint.resume(*learner, envs)) {
    reported = extra->at("reported").get<std::size_t>();
    EXPECT_EQ(std::int64_t(reported), checkpoint.updates());
    run.stats.resize(reported);  // what came after the checkpoint is reported again
  }
  int seen = 0;
  learner->train_until(envs, total, [&](const TrainStats& s) {
    run.stats.push_back({s.env_steps, s.episodes, s.mean_return});
    checkpoint.on_update(*learner, envs, {{"reported", run.stats.size()}});
    if (++seen == stop_after) throw Stop{};
  });
  run.parameters = learner->parameters();
}

void check_resume(const std::string& algorithm, std::int64_t total) {
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_tc_" + algorithm + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Run uninterrupted, interrupted;
  attempt(algorithm, dir / "a.ckpt", total, 0, uninterrupted);
  ASSERT_GE(uninterrupted.stats.size(), 10u);
  // Stopped after 3 updates (checkpoint at 2), then after 4 more (checkpoint at 6), then finished.
  EXPECT_THROW(attempt(algorithm, dir / "b.ckpt", total, 3, interrupted), Stop);
  EXPECT_THROW(attempt(algorithm, dir / "b.ckpt", total, 5, interrupted), Stop);
  attempt(algorithm, dir / "b.ckpt", total, 0, interrupted);
  EXPECT_TRUE(interrupted.stats == uninterrupted.stats) << algorithm << ": per-update stats differ";
  EXPECT_TRUE(interrupted.parameters == uninterrupted.parameters) << algorithm << ": final parameters differ";
  EXPECT_FALSE(fs::exists(dir / "b.ckpt.tmp"));
  fs::remove_all(dir);
}

struct Point {
  std::string name;
  double step, value;
  bool operator==(const Point& o) const {
    return name == o.name && step == o.step && (value == o.value || (std::isnan(value) && std::isnan(o.value)));
  }
};

// PPO to 1500 steps, a checkpoint every 2 updates, two metrics per update through the checkpoint
// (mean_return is NaN while no episode has ended); throws Stop after `stop_after` updates of this
// attempt (0: never). `received`: every point the sink got, replays included.
void metric_attempt(const fs::path& file, int stop_after, std::vector<Point>& received) {
  auto learner = make("ppo");
  auto envs = pendulums();
  TrainingCheckpoint checkpoint(file, 2, [&](const std::string& name, double step, double value) {
    received.push_back({name, step, value});
  });
  checkpoint.resume(*learner, envs);
  int seen = 0;
  learner->train_until(envs, 1500, [&](const TrainStats& s) {
    const auto update = static_cast<double>(checkpoint.updates() + 1);
    checkpoint.metric("mean_return", update, s.mean_return);
    checkpoint.metric("env_steps", update, static_cast<double>(s.env_steps));
    checkpoint.on_update(*learner, envs, nullptr);
    if (++seen == stop_after) throw Stop{};
  });
}

// Keeps the first value of each (name, step), as the store does.
std::map<std::pair<std::string, double>, Point> deduplicated(const std::vector<Point>& points) {
  std::map<std::pair<std::string, double>, Point> kept;
  for (const auto& p : points) kept.emplace(std::pair(p.name, p.step), p);
  return kept;
}

TEST(TrainingCheckpoint, AResumeSendsAgainExactlyThePointsItsCheckpointHolds) {
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_tc_metrics_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<Point> killed, resumed, uninterrupted;
  // Killed after update 5, its checkpoint at 4: the sink got updates 1-5, the store may lack any.
  EXPECT_THROW(metric_attempt(dir / "m.ckpt", 5, killed), Stop);
  std::vector<Point> checkpointed;
  std::copy_if(killed.begin(), killed.end(), std::back_inserter(checkpointed), [](const Point& p) { return p.step <= 4; });
  std::stable_sort(checkpointed.begin(), checkpointed.end(), [](const Point& a, const Point& b) { return a.name < b.name; });
  ASSERT_EQ(checkpointed.size(), 8u);
  ASSERT_TRUE(std::isnan(checkpointed.back().value));  // a NaN survives the checkpoint's JSON

  metric_attempt(dir / "m.ckpt", 0, resumed);
  ASSERT_GT(resumed.size(), checkpointed.size());
  // The fresh object's resume() replays them all before training continues at update 5.
  EXPECT_TRUE(std::equal(checkpointed.begin(), checkpointed.end(), resumed.begin()));
  EXPECT_EQ(resumed[checkpointed.size()], (Point{"mean_return", 5, killed[8].value}));

  // Whatever of the killed attempt reached the store, a de-duplicating store ends with the
  // uninterrupted run's points; here: none of it did.
  metric_attempt(dir / "u.ckpt", 0, uninterrupted);
  EXPECT_TRUE(deduplicated(resumed) == deduplicated(uninterrupted));
  std::vector<Point> all = killed;
  all.insert(all.end(), resumed.begin(), resumed.end());
  EXPECT_TRUE(deduplicated(all) == deduplicated(uninterrupted));
  fs::remove_all(dir);
}

TEST(TrainingCheckpoint, PpoStoppedTwiceAndResumedEqualsUninterruptedRun) { check_resume("ppo", 1500); }

TEST(TrainingCheckpoint, SacStoppedTwiceAndResumedEqualsUninterruptedRun) { check_resume("sac", 1200); }

TEST(TrainingCheckpoint, NoFileMeansAFreshStartAndATornTempFileIsIgnored) {
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_tc_fresh_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "c.ckpt.tmp") << "half a checkpoint";  // a kill during a save
  auto learner = make("ppo");
  auto envs = pendulums();
  TrainingCheckpoint checkpoint(dir / "c.ckpt", 1);
  EXPECT_FALSE(checkpoint.resume(*learner, envs).has_value());
  learner->train_until(envs, 120, [&](const TrainStats&) { checkpoint.on_update(*learner, envs, nullptr); });
  EXPECT_TRUE(fs::exists(dir / "c.ckpt"));
  auto fresh = make("ppo");
  auto fresh_envs = pendulums();
  TrainingCheckpoint again(dir / "c.ckpt", 1);
  const auto extra = again.resume(*fresh, fresh_envs);
  ASSERT_TRUE(extra.has_value());
  EXPECT_TRUE(extra->is_null());
  EXPECT_EQ(again.updates(), 1);
  EXPECT_EQ(fresh->parameters(), learner->parameters());
  EXPECT_THROW(TrainingCheckpoint(dir / "d.ckpt", 0), base::UserError);
  EXPECT_THROW(TrainingCheckpoint(dir / "d.ckpt", 1).metric("x", 0, 1), base::RuntimeError);  // no sink
  // A damaged file (not one of ours: ours are renamed into place whole) is one line naming it.
  std::ofstream(dir / "e.ckpt") << "garbage";
  try {
    TrainingCheckpoint(dir / "e.ckpt", 1).resume(*fresh, fresh_envs);
    ADD_FAILURE() << "expected a RuntimeError";
  } catch (const base::RuntimeError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("e.ckpt cannot be read"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  fs::remove_all(dir);
}

// A warm start copies another run's checkpoint in only while there is none of its own: a later
// attempt resumes from its own saves, not from the source again.
TEST(TrainingCheckpoint, StartFromCopiesTheSourceOnlyWhenNoCheckpointExists) {
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_tc_warm_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto learner = make("ppo");
  auto envs = pendulums();
  TrainingCheckpoint source(dir / "source.ckpt", 1);
  learner->train_until(envs, 120, [&](const TrainStats&) { source.on_update(*learner, envs, "source"); });

  TrainingCheckpoint warm(dir / "warm.ckpt", 1);
  EXPECT_TRUE(warm.start_from(dir / "source.ckpt"));
  EXPECT_FALSE(fs::exists(dir / "warm.ckpt.warm"));
  auto trained_on = make("ppo");
  auto trained_on_envs = pendulums();
  EXPECT_EQ(warm.resume(*trained_on, trained_on_envs), base::Json("source"));
  EXPECT_EQ(trained_on->parameters(), learner->parameters());
  warm.on_update(*trained_on, trained_on_envs, "own");
  EXPECT_FALSE(TrainingCheckpoint(dir / "warm.ckpt", 1).start_from(dir / "source.ckpt"));
  auto again = make("ppo");
  auto again_envs = pendulums();
  EXPECT_EQ(TrainingCheckpoint(dir / "warm.ckpt", 1).resume(*again, again_envs), base::Json("own"));

  try {
    TrainingCheckpoint(dir / "other.ckpt", 1).start_from(dir / "missing.ckpt");
    ADD_FAILURE() << "expected a UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.ckpt"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "other.ckpt"));
  fs::remove_all(dir);
}

// A checkpoint of another format version (here one an older build wrote, without a version) is
// refused with one line that names the file and says what to do, before anything is read from it.
TEST(TrainingCheckpoint, AFileOfAnotherFormatVersionIsRefusedWithWhatToDo) {
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_tc_format_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto learner = make("ppo");
  auto envs = pendulums();
  learner->train_until(envs, 120);
  learner->save_checkpoint(dir / "old.ckpt", envs, {{"updates", 1}, {"metrics", base::Json::object()}, {"extra", nullptr}});
  learner->save_checkpoint(dir / "next.ckpt", envs,
                           {{"format", TrainingCheckpoint::kFormatVersion + 1},
                            {"updates", 1},
                            {"metrics", base::Json::object()},
                            {"extra", nullptr}});
  for (const char* file : {"old.ckpt", "next.ckpt"}) {
    auto fresh = make("ppo");
    auto fresh_envs = pendulums();
    try {
      TrainingCheckpoint(dir / file, 1).resume(*fresh, fresh_envs);
      ADD_FAILURE() << file << ": expected a UserError";
    } catch (const base::UserError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file), std::string::npos) << what;
      EXPECT_NE(what.find("delete it to train the trial from scratch"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace podium::learn
