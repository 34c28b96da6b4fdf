#pragma once
/// The training-stage driver: the one loop every learning stage of a task runs. It owns what all
/// stages share: building the learner, resume after a kill and warm start, the wall-clock budget,
/// cancellation, progress, the test cadence, metric points through learn::TrainingCheckpoint (kept
/// with each checkpoint and sent again on resume), the export of the policy with a typed record of
/// what was exported and why, checkpointing (one file per kind of environment copies, for a stage
/// that rebuilds them at a new control rate), and the final recording of the exported policy. A
/// task supplies only what is its own, by deriving from TrainingStage: its environment copies, its
/// schedule (curriculum, κ, z), its test statistic and metrics, and its export rule.
///
///     class MyStage final : public character::TrainingStage {
///      public:
///       void build(const base::Json&) override { envs_ = make_copies(); }
///       learn::VecEnv& envs() override { return *envs_; }
///       base::Json learner_spec() const override { return {{"algorithm", "ppo"}}; }
///       character::Figures test(const character::TestRound& round, learn::Learner& learner,
///                               const character::MetricFn& send) override {
///         const double r = mean_test_return(learner);
///         send("test_return", static_cast<double>(round.env_steps), r);
///         return {{"test_return", r}};
///       }
///       void record(const character::Recording& r) override { trajectory_ = record_motion(r.policy, r.rollouts); }
///      ...
///     };
///     MyStage stage(settings);
///     const character::StageOutcome out = character::run_training_stage(
///         stage, {.name = "my task", .total_steps = 1'000'000, .steps_per_iteration = 1, .test_every = 10},
///         {.seed = request.seed, .work_dir = request.work_dir, .cancel = request.cancel,
///          .report = character::Reporter::to(sink)});
///
/// The loop, per iteration: train_until(env steps + steps_per_iteration) (cancellation checked at
/// every TrainCallback: a PPO iteration or a SAC log interval), on_iteration(), a test every
/// test_every iterations (test(), then the export rule), progress, and a checkpoint every
/// checkpoint_every iterations; until total_steps, the stage's finished() or the wall budget.
/// After training, when no test exported a policy, the final one is exported (reason `last`);
/// record() then sees the exported file. A run is deterministic for a seed: the learner is seeded
/// with base::derive_seed(seed, 2) (the task seeds its copies), and a resumed run ends bitwise as an
/// uninterrupted one, with the same metric points, except the `time/` series.
///
/// What it is built for: PPO or SAC (learner_spec(); steps_per_iteration = 1 makes an iteration one
/// PPO iteration, a SAC stage trains to its next test in one), a curriculum fed every iteration
/// (on_iteration()) or at each test (test()), copies rebuilt mid-run at another control rate
/// (checkpoint_tag(), build_state()), a stage that trains on from a policy or a checkpoint handed
/// over (StageSettings::warm_start), and one that hands states on as well as its policy: record()
/// writes them (beside the recorded motions) for the task to return as artifacts.
///
/// Wall times are metrics under `time/`, one point per test at its environment step, so reports
/// never parse log text: time/rollout_s and time/update_s (the learner's rollouts and updates since
/// the previous test), time/test_s (the test) and time/wall_s (everything since the previous test:
/// training, tests, exports, checkpoints). They are the only series that differ between two runs
/// of a seed, and a resumed run keeps the first value stored for each point.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/learn/frozen_policy.h"
#include "podium/learn/learner.h"
#include "podium/learn/vec_env.h"

namespace podium::character {

/// One metric point: name, step, value.
using MetricFn = std::function<void(const std::string& name, double step, double value)>;

/// Where a stage reports: metric points and progress (a plugins::Sink without the plugin types).
struct Reporter {
  MetricFn metric;
  std::function<void(double fraction)> progress;
  /// Reports to a plugins::Sink (anything with its metric() and progress()), which must outlive it.
  template <class Sink>
  static Reporter to(Sink& sink) {
    return {[&sink](const std::string& name, double step, double value) { sink.metric(name, step, value); },
            [&sink](double fraction) { sink.progress(fraction); }};
  }
};

/// A test's statistic, by name (e.g. test_return, success_rate, the strength tested at).
using Figures = std::map<std::string, double>;
/// The figure `name` of `figures`; throws std::logic_error naming it when absent.
double figure(const Figures& figures, const std::string& name);

/// Why the exported policy was exported.
enum class ExportReason {
  passed,  ///< it passed the task's test criterion (e.g. a curriculum level)
  best,    ///< the best tested so far by the task's ranking
  last,    ///< the policy at the end of training (no test exported one)
};
std::string to_string(ExportReason reason);

/// One figure of a ranking, and which way is better.
struct RankBy {
  std::string name;
  bool higher_is_better = true;
};
struct ExportRecord;
/// The export rule "the best tested so far": ExportReason::best when nothing is exported yet or
/// `tested`'s figures beat `exported`'s in the order of `ranking` (the first that differs decides;
/// a tie keeps the earlier policy), else nothing.
std::optional<ExportReason> best_by(const ExportRecord& tested, const ExportRecord* exported, const std::vector<RankBy>& ranking);

/// What was exported, at which test and environment step, and why.
struct ExportRecord {
  ExportReason reason = ExportReason::last;
  int test = 0;                ///< the test (1, 2, ...; 0: before training) whose figures these are
  std::int64_t env_steps = 0;  ///< the learner's environment steps when it was exported
  Figures figures;             ///< that test's (empty for `last` when no test ran)
  base::Json to_json() const;
  static ExportRecord from_json(const base::Json& json);
};

/// Statistics of the training since some point (an iteration, or the previous test).
struct TrainingTally {
  learn::TrainStats last;   ///< the last TrainCallback's (a PPO iteration: its only one)
  double return_sum = 0.0;  ///< Σ mean_return · episodes over the callbacks that ended episodes
  std::size_t episodes = 0;
  double rollout_s = 0.0, update_s = 0.0;  ///< wall seconds (vary between runs: logs and time/ only)
  /// Mean return of the episodes that ended (NaN when none did).
  double mean_return() const;
};

/// What on_iteration() is told.
struct Iteration {
  std::int64_t index = 0;             ///< 1, 2, ... counting those before a resume
  std::int64_t env_steps_before = 0;  ///< the learner's environment steps before it
  std::int64_t env_steps = 0;         ///< and after
  TrainingTally training;             ///< of this iteration
};

/// What test() is told.
struct TestRound {
  int test = 0;                ///< 1, 2, ...; 0: the test before training (StageSettings)
  std::int64_t iteration = 0;  ///< iterations so far
  std::int64_t env_steps = 0;
  TrainingTally training;  ///< since the previous test
  /// Wall seconds since the test began (for a log line; the driver sends time/test_s).
  double seconds() const;
  std::chrono::steady_clock::time_point started;  ///< when the test began (set by the driver)
};

/// What record() is handed after training.
struct Recording {
  const ExportRecord& exported;
  const std::filesystem::path& file;  ///< the exported policy's TorchScript file
  const learn::FrozenPolicy& policy;  ///< loaded from it (its actions equal the learner's exactly)
  const learn::Learner& learner;      ///< the final learner (its parameters; not the exported policy unless `last`)
  const MetricFn& send;               ///< metric points (after the last checkpoint: not kept)
  std::filesystem::path rollouts;     ///< work_dir/rollouts, for recorded motions
};

/// The task's part of a training stage. Every hook but build(), envs(), learner_spec() and test()
/// has a default that does nothing.
class TrainingStage {
 public:
  virtual ~TrainingStage() = default;

  /// Builds the training copies, once, before the learner. `built` is build_state() as saved with
  /// the checkpoint the run resumes from, null on a fresh start.
  virtual void build(const base::Json& built) = 0;
  /// The copies training steps now (on_iteration() may rebuild them).
  virtual learn::VecEnv& envs() = 0;
  /// learn::make_learner's spec: algorithm, preset, config.
  virtual base::Json learner_spec() const = 0;
  /// The checkpoint file's tag for the current copies: "" → training.ckpt; "12hz" →
  /// training_12hz.ckpt. A checkpoint loads only into copies like those it saved, so a stage that
  /// rebuilds its copies as another kind (a new control rate) names each kind; after the first
  /// save under a new tag the older files go.
  virtual std::string checkpoint_tag() const { return ""; }
  /// What build() needs to build the current copies again (e.g. the bar they were built at); kept
  /// beside each tagged checkpoint file (training_<tag>.json).
  virtual base::Json build_state() const { return nullptr; }

  /// The task's own state (curriculum, κ, what it reports at the end), kept with each checkpoint.
  virtual base::Json state() const { return nullptr; }
  /// Loads state() from the checkpoint resumed from (also a warm start's source's).
  virtual void load_state(const base::Json& /*state*/) {}
  /// Once before training, after load_state() on a resume and the warm start (e.g. to set the
  /// strength the copies train at, or to hold a curriculum).
  virtual void begin(bool /*resumed*/, learn::Learner& /*learner*/) {}

  /// After every iteration: feed a curriculum, rebuild the copies, send per-iteration metrics.
  virtual void on_iteration(const Iteration& /*iteration*/, learn::Learner& /*learner*/, const MetricFn& /*send*/) {}
  /// Whether training ends before total_steps (e.g. a curriculum's last level).
  virtual bool finished() const { return false; }
  /// The stage's progress in [0, 1] beyond the driver's (steps and wall budget used).
  virtual double progress() const { return 0.0; }

  /// Tests the learner's deterministic policy, sends the test's metrics, returns its statistic.
  /// The schedule may move here (a curriculum decides at its tests).
  virtual Figures test(const TestRound& round, learn::Learner& learner, const MetricFn& send) = 0;
  /// The export rule, after each test: whether the tested policy replaces the exported one
  /// (`exported`, null before the first export) and why; nullopt keeps it.
  virtual std::optional<ExportReason> export_rule(const ExportRecord& /*tested*/, const ExportRecord* /*exported*/) {
    return std::nullopt;
  }

  /// After training and the final export: records the exported policy's motion and features.
  virtual void record(const Recording& /*recording*/) {}
};

/// How the driver runs a stage.
struct StageSettings {
  std::string name = {};         ///< in log lines and errors: "getup", "jump"
  std::int64_t total_steps = 0;  ///< environment steps at most (≥ 1)
  /// An iteration trains until env_steps + this: 1 = one PPO iteration; SAC: e.g. the test interval.
  std::int64_t steps_per_iteration = 1;
  int test_every = 1;                 ///< iterations between tests (≥ 1)
  bool test_before_training = false;  ///< also test at step 0 (test 0), on a fresh start only
  int checkpoint_every = 1;           ///< iterations between checkpoints (≥ 1)
  double train_minutes = 0.0;         ///< wall-clock budget of training and tests (learn::WallBudget); 0: none
  /// "": from scratch. Otherwise on a fresh start (no checkpoint of this trial yet):
  enum class WarmStart {
    checkpoint,  ///< another trial's training checkpoint: networks, buffers, copies, steps, state(), metric points; not its
                 ///< export record nor its clock
    policy,      ///< a policy file (learn::Learner::warm_start): its networks, everything else fresh
  };
  std::filesystem::path warm_start = {};
  WarmStart warm_start_kind = WarmStart::checkpoint;
};

/// The trial a stage runs in, as the plugin hands it.
struct StageRun {
  std::uint64_t seed = 0;
  std::filesystem::path work_dir = {};  ///< the trial folder: checkpoints, policy.pt, rollouts/
  const std::atomic<bool>* cancel = nullptr;
  Reporter report = {};
};

struct StageOutcome {
  ExportRecord exported;
  std::filesystem::path policy;  ///< work_dir/policy.pt
  std::int64_t env_steps = 0;
  std::int64_t iterations = 0;
  int tests = 0;
  /// What ended training: "steps" (total_steps), "time" (train_minutes) or "schedule" (finished()).
  std::string stopped_by = "steps";
};

/// Runs `stage` in `run.work_dir`, resuming from its checkpoint when a previous attempt left one
/// (metric points it covers are sent again; the store drops repeats). Throws std::runtime_error
/// when `run.cancel` is set (checked at every TrainCallback and before every iteration), and
/// base::UserError for a checkpoint of another format version or a bad warm start.
StageOutcome run_training_stage(TrainingStage& stage, const StageSettings& settings, const StageRun& run);

/// The time/ series' descriptions, for a task's describe(): [{name, unit, description, x, kind}]
/// (plugins::metric_entry's shape: learning curves over environment steps).
base::Json time_metric_entries();

}  // namespace podium::character
