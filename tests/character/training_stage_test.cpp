// The training-stage driver on a tiny scripted stage (PPO on learn's Pendulum, 16 environment
// steps per iteration): a run killed mid-way and resumed ends as the uninterrupted one (also when
// its checkpoint file changes tag), a cancel throws at the next iteration, the export rule decides
// what is exported, the wall budget stops training, and a warm start trains on from a checkpoint.
#include "podium/character/training_stage.h"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>

#include "podium/base/error.h"
#include "podium/learn/classic_control.h"
#include "process.h"

namespace podium::character {
namespace {

namespace fs = std::filesystem;
using base::Json;

const std::vector<double> kObservation = {0.3, -0.8, 0.5};  // a Pendulum observation (cos, sin, θ̇)

// What the scripted stage does beyond training.
struct Script {
  std::vector<double> scores = {1.0};    // test i's score: scores[(i − 1) mod n]
  bool export_best = false;              // the export rule: the best score so far
  std::int64_t cancel_at_iteration = 0;  // sets `cancel` in that iteration's hook
  std::atomic<bool>* cancel = nullptr;
  std::int64_t retag_at_iteration = 0;  // from then on its checkpoint file is training_b.ckpt
};

class ScriptedStage final : public TrainingStage {
 public:
  explicit ScriptedStage(Script script) : script_(std::move(script)) {}

  void build(const Json& built) override {
    tag_ = built.is_null() ? (script_.retag_at_iteration > 0 ? "a" : "") : built.at("tag").get<std::string>();
    std::vector<std::unique_ptr<learn::Env>> copies;
    for (int i = 0; i < 2; ++i) copies.push_back(std::make_unique<learn::Pendulum>());
    envs_ = std::make_unique<learn::VecEnv>(std::move(copies), 1, 11);
  }
  learn::VecEnv& envs() override { return *envs_; }
  Json learner_spec() const override {
    return {{"algorithm", "ppo"},
            {"preset", "quick"},
            {"config", {{"hidden", {8}}, {"rollout_steps", 8}, {"epochs", 1}, {"minibatch_size", 16}}}};
  }
  std::string checkpoint_tag() const override { return tag_; }
  Json build_state() const override { return {{"tag", tag_}}; }
  Json state() const override { return {{"iterations", iterations_}}; }
  void load_state(const Json& state) override { iterations_ = state.at("iterations").get<std::int64_t>(); }

  void on_iteration(const Iteration& it, learn::Learner&, const MetricFn& send) override {
    iterations_ = it.index;
    send("iteration", static_cast<double>(it.env_steps), static_cast<double>(it.index));
    if (it.index == script_.cancel_at_iteration) *script_.cancel = true;
    if (it.index == script_.retag_at_iteration) tag_ = "b";
  }
  Figures test(const TestRound& round, learn::Learner& learner, const MetricFn& send) override {
    std::vector<double> action(1);
    learner.act(kObservation, action, true);
    actions_[round.test] = action[0];
    const double score = script_.scores[static_cast<std::size_t>(round.test - 1) % script_.scores.size()];
    send("score", static_cast<double>(round.env_steps), score);
    send("action", static_cast<double>(round.env_steps), action[0]);  // depends on every parameter
    return {{"score", score}};
  }
  std::optional<ExportReason> export_rule(const ExportRecord& tested, const ExportRecord* exported) override {
    if (!script_.export_best) return std::nullopt;
    if (!exported || figure(tested.figures, "score") > figure(exported->figures, "score")) return ExportReason::best;
    return std::nullopt;
  }
  void record(const Recording& r) override {
    std::vector<double> action(1);
    r.policy.act(kObservation, action);
    recorded_action = action[0];
    parameters = r.learner.parameters();
  }

  std::map<int, double> actions_;  // the deterministic action at kObservation, by test
  double recorded_action = 0.0;    // the exported policy's, at the end
  std::vector<float> parameters;   // the final learner's

 private:
  Script script_;
  std::string tag_;
  std::int64_t iterations_ = 0;
  std::unique_ptr<learn::VecEnv> envs_;
};

struct Record {
  std::map<std::pair<std::string, double>, double> metrics;  // a point sent again overwrites itself
  std::vector<double> progress;
  StageOutcome out;
  std::map<int, double> actions;
  double recorded_action = 0.0;
  std::vector<float> parameters;
};

StageSettings settings(std::int64_t total_steps = 8 * 16) {
  return {.name = "scripted", .total_steps = total_steps, .test_every = 2, .checkpoint_every = 1};
}

// Runs the stage in `dir`, adding what it reports to `run`.
void run_stage(const Script& script, const StageSettings& s, const fs::path& dir, const std::atomic<bool>* cancel, Record& run) {
  ScriptedStage stage(script);
  const Reporter report{[&](const std::string& name, double step, double value) {
                          if (name.rfind("time/", 0) != 0) run.metrics[{name, step}] = value;
                        },
                        [&](double f) { run.progress.push_back(f); }};
  run.out = run_training_stage(stage, s, {.seed = 5, .work_dir = dir, .cancel = cancel, .report = report});
  run.actions = stage.actions_;
  run.recorded_action = stage.recorded_action;
  run.parameters = stage.parameters;
}

std::string bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void expect_resume_equals_uninterrupted(std::int64_t retag_at) {
  podium::testing::TempDir whole, cut;
  Record full;
  run_stage({.retag_at_iteration = retag_at}, settings(), whole.path(), nullptr, full);

  std::atomic<bool> cancel{false};
  Record resumed;
  EXPECT_THROW(run_stage({.cancel_at_iteration = 5, .cancel = &cancel, .retag_at_iteration = retag_at}, settings(), cut.path(),
                         &cancel, resumed),
               std::runtime_error);
  resumed.progress.clear();
  run_stage({.retag_at_iteration = retag_at}, settings(), cut.path(), nullptr, resumed);

  EXPECT_EQ(resumed.metrics, full.metrics);
  EXPECT_EQ(resumed.parameters, full.parameters);
  EXPECT_EQ(bytes(cut / "policy.pt"), bytes(whole / "policy.pt"));
  EXPECT_EQ(resumed.out.iterations, 8);
  EXPECT_EQ(resumed.out.tests, 4);
  EXPECT_EQ(resumed.out.exported.to_json(), full.out.exported.to_json());
  ASSERT_FALSE(resumed.progress.empty());
  EXPECT_DOUBLE_EQ(resumed.progress.front(), 5.0 / 8.0);  // from its checkpoint of iteration 5
  EXPECT_EQ(resumed.progress.back(), 1.0);
}

TEST(TrainingStage, AResumedRunEndsAsTheUninterruptedOne) { expect_resume_equals_uninterrupted(0); }

// The checkpoint file follows the copies' tag (training_a.ckpt, then training_b.ckpt from
// iteration 3 on, the older file removed after the first save under the new tag).
TEST(TrainingStage, AResumedRunEndsAsTheUninterruptedOneAcrossATagChange) {
  expect_resume_equals_uninterrupted(3);
  podium::testing::TempDir dir;
  Record run;
  run_stage({.retag_at_iteration = 3}, settings(), dir.path(), nullptr, run);
  EXPECT_TRUE(fs::exists(dir / "training_b.ckpt"));
  EXPECT_EQ(base::read_json_file(dir / "training_b.json").at("build"), (Json{{"tag", "b"}}));
  EXPECT_FALSE(fs::exists(dir / "training_a.ckpt"));
  EXPECT_FALSE(fs::exists(dir / "training_a.json"));
  EXPECT_FALSE(fs::exists(dir / "training.ckpt"));
}

TEST(TrainingStage, ACancelThrowsAtTheNextIteration) {
  podium::testing::TempDir dir;
  std::atomic<bool> cancel{false};
  Record run;
  try {
    run_stage({.cancel_at_iteration = 3, .cancel = &cancel}, settings(), dir.path(), &cancel, run);
    ADD_FAILURE() << "expected the cancel to throw";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "scripted: cancelled at environment step 48");  // after iteration 3's 3 × 16 steps
  }
  EXPECT_TRUE(run.metrics.count({"iteration", 48.0}));
  EXPECT_FALSE(run.metrics.count({"iteration", 64.0}));  // iteration 4 never trained
  EXPECT_FALSE(fs::exists(dir / "policy.pt"));
}

// Best by score: the scores 1, 3, 2, 5 at tests 1-4 export test 4's policy; with no rule, the
// last policy is exported (reason last) with the last test's figures.
TEST(TrainingStage, BestByRanksByItsFiguresInOrder) {
  const auto record = [](double rate, double error) {
    ExportRecord r;
    r.figures = {{"rate", rate}, {"error", error}};
    return r;
  };
  const std::vector<RankBy> ranking = {{"rate"}, {"error", false}};
  const ExportRecord exported = record(0.5, 0.2);
  EXPECT_EQ(best_by(record(0.0, 9.0), nullptr, ranking), ExportReason::best);    // the first tested
  EXPECT_EQ(best_by(record(0.6, 9.0), &exported, ranking), ExportReason::best);  // a higher rate decides
  EXPECT_EQ(best_by(record(0.4, 0.0), &exported, ranking), std::nullopt);        // a lower one too
  EXPECT_EQ(best_by(record(0.5, 0.1), &exported, ranking), ExportReason::best);  // a tie: the smaller error
  EXPECT_EQ(best_by(record(0.5, 0.3), &exported, ranking), std::nullopt);
  EXPECT_EQ(best_by(record(0.5, 0.2), &exported, ranking), std::nullopt);  // a full tie keeps the earlier
  EXPECT_THROW(best_by(record(0.5, 0.2), &exported, {{"missing"}}), std::logic_error);
}

TEST(TrainingStage, TheExportRuleDecidesWhatIsExported) {
  podium::testing::TempDir best_dir, last_dir;
  Record best;
  run_stage({.scores = {1.0, 3.0, 2.0, 5.0, 4.0}, .export_best = true}, settings(10 * 16), best_dir.path(), nullptr, best);
  EXPECT_EQ(best.out.exported.reason, ExportReason::best);
  EXPECT_EQ(best.out.exported.test, 4);
  EXPECT_EQ(best.out.exported.env_steps, 8 * 16);
  EXPECT_EQ(best.out.exported.figures, (Figures{{"score", 5.0}}));
  EXPECT_EQ(best.recorded_action, best.actions.at(4));  // the policy tested at test 4, not the last
  EXPECT_NE(best.recorded_action, best.actions.at(5));

  Record last;
  run_stage({.scores = {1.0, 3.0, 2.0, 5.0, 4.0}}, settings(10 * 16), last_dir.path(), nullptr, last);
  EXPECT_EQ(last.out.exported.reason, ExportReason::last);
  EXPECT_EQ(last.out.exported.test, 5);
  EXPECT_EQ(last.out.exported.env_steps, 10 * 16);
  EXPECT_EQ(last.out.exported.figures, (Figures{{"score", 4.0}}));
  EXPECT_EQ(last.recorded_action, last.actions.at(5));
  EXPECT_EQ(ExportRecord::from_json(best.out.exported.to_json()).to_json(), best.out.exported.to_json());
}

// A budget of 1e-9 minutes is used up by the first iteration: training stops after it.
TEST(TrainingStage, TheWallBudgetStopsTraining) {
  podium::testing::TempDir dir;
  StageSettings s = settings();
  s.train_minutes = 1e-9;
  Record run;
  run_stage({}, s, dir.path(), nullptr, run);
  EXPECT_EQ(run.out.stopped_by, "time");
  EXPECT_EQ(run.out.iterations, 1);
  EXPECT_EQ(run.out.env_steps, 16);
}

// Trained on from another run's checkpoint: its steps, metric points and state carry over, its
// export record does not; the steps go on to the new total.
TEST(TrainingStage, AWarmStartTrainsOnFromAnotherRunsCheckpoint) {
  podium::testing::TempDir source_dir, warm_dir;
  const Script script{.scores = {1.0, 3.0, 2.0, 5.0, 0.5, 0.7}, .export_best = true};
  Record source;
  run_stage(script, settings(), source_dir.path(), nullptr, source);
  ASSERT_EQ(source.out.exported.test, 4);
  StageSettings s = settings(12 * 16);
  s.warm_start = source_dir / "training.ckpt";
  Record warm;
  run_stage(script, s, warm_dir.path(), nullptr, warm);
  EXPECT_EQ(warm.out.iterations, 12);
  for (const auto& [key, value] : source.metrics) EXPECT_EQ(warm.metrics.at(key), value) << key.first << " " << key.second;
  EXPECT_EQ(warm.out.exported.test, 6);  // the best of its own tests 5 and 6, not the source's test 4
  EXPECT_EQ(warm.out.exported.figures, (Figures{{"score", 0.7}}));
}

TEST(TrainingStage, BadSettingsAreAProgrammersError) {
  podium::testing::TempDir dir;
  StageSettings s = settings();
  s.test_every = 0;
  Record run;
  EXPECT_THROW(run_stage({}, s, dir.path(), nullptr, run), std::logic_error);
}

}  // namespace
}  // namespace podium::character
