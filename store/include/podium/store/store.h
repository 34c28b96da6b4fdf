#pragma once
/// The store: Podium's SQLite database, its schema and migrations, and typed reads and writes.
/// No other code opens the database file.
///
/// Contract (Optuna's storage contract, adapted):
/// - Writers: only the scheduler writes trial data while a campaign runs; the CLI writes the
///   campaign rows it submits and control states (pause, resume, cancel). Readers (status,
///   export, the dashboard) open the file read-only and never hold a transaction across calls.
/// - Every multi-row write goes in one transaction (`transaction(fn)`); SQLite in WAL mode with
///   foreign keys on and a busy timeout, so readers never block the scheduler.
/// - Records are snapshots: plain structs copied out of the database.
/// - Trial states: pending → running → done | failed | interrupted | cancelled;
///   interrupted → running (run again). done and failed are final; a finished trial's result
///   is never rewritten.
/// - Attempt states: running → done | failed | timeout | interrupted | cancelled.
/// - Campaign states: queued, running, paused, done, failed, cancelled.
/// - schema_version with one forward migration per version; a database newer than this build
///   is refused without being touched.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::store {

using base::Json;

struct NewStage {
  std::string name, task, algorithm;
  Json search_config = Json::object();
  Json task_config = Json::object();  ///< resolved: defaults, preset, overrides
  Json description = Json::object();  ///< the task's describe() for that config
  Json inputs = nullptr;              ///< the spec's hand-over rule (orchestrator's InputsSpec) or null
  std::int64_t budget_trials = 0;     ///< 0: set by start_stage (a budget per input)
  double budget_seconds = 0.0;        ///< 0: no wall-time budget
};

struct CampaignRecord {
  std::int64_t id = 0;
  std::string name, state, run_dir, error, podium_version;
  Json spec;
  std::uint64_t seed = 0;
  double created_at = 0, started_at = 0, finished_at = 0;  ///< unix seconds; 0 = not yet
};

struct StageRecord {
  std::int64_t id = 0, campaign_id = 0;
  int index = 0;
  std::string name, task, algorithm, state;  ///< state: waiting, running, done, failed
  std::string error;                         ///< why it failed ("" otherwise)
  Json search_config, task_config, description, inputs;
  std::optional<Json> input_trials;  ///< the trials handed over, resolved by start_stage
  std::int64_t budget_trials = 0;
  double budget_seconds = 0, elapsed_s = 0;
  std::optional<Json> search_state;
  std::int64_t told = 0;  ///< trials (in the order asked) told to the search
};

struct TrialRecord {
  std::int64_t id = 0, stage_id = 0, index = 0;
  Json params, context, info;
  std::uint64_t seed = 0;
  std::string state, error;
  int attempts = 0;
  Json objectives = nullptr;  ///< array once done
  std::vector<double> features;
  Json result_info = nullptr;
  std::optional<std::int64_t> strategy;
  double created_at = 0, started_at = 0, finished_at = 0;
};

/// A done trial as a campaign summary reads it: a few columns, no params, info or features.
struct TrialOutcome {
  std::int64_t id = 0, index = 0;
  std::optional<double> objective;  ///< objectives[0] (absent when not a number)
  std::optional<std::int64_t> strategy;
  double finished_at = 0;
  std::string result_info;  ///< its result info's JSON text when it has a "table", else ""
};

/// A stage's strategies as users read them: the store's id (a cell of the strategy grid, the key in
/// filters, URLs and the search) -> 1..n in the order the strategies were first found (done trials
/// in the order they finished, the lower index first on a tie), so "strategy 3" is the third found.
using StrategyLabels = std::map<std::int64_t, std::int64_t>;

struct AttemptRecord {
  std::int64_t id = 0, trial_id = 0;
  int number = 0;
  std::string state, worker, host, error, job_id;
  std::optional<int> exit_code, signal;
  double started_at = 0, finished_at = 0;
};

struct MetricPoint {
  std::string name;
  double step = 0, value = 0;
  int attempt = 1;
};

struct ArtifactRecord {
  std::string name, path, sha256;
  std::int64_t size_bytes = 0;
};

struct TrialCounts {
  std::int64_t total = 0, pending = 0, running = 0, done = 0, failed = 0, interrupted = 0, cancelled = 0;
};

class Store {
 public:
  enum class Access { read_write, read_only };

  /// Opens (read_write: creates and migrates) the database. Throws base::RuntimeError naming the
  /// file and the reason (cannot open, not a Podium database, schema newer than this build).
  static std::unique_ptr<Store> open(const std::filesystem::path& path, Access access);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  static int latest_schema_version();
  int schema_version() const;
  const std::filesystem::path& path() const;

  /// Runs fn inside one write transaction (BEGIN IMMEDIATE … COMMIT; rolled back if fn throws).
  template <class Fn>
  void transaction(Fn&& fn) {
    begin();
    try {
      fn();
    } catch (...) {
      rollback();
      throw;
    }
    commit();
  }
  void begin();
  void commit();
  void rollback();

  // Campaigns and stages.
  std::int64_t add_campaign(const std::string& name, const Json& spec, std::uint64_t seed, const std::string& run_dir,
                            const std::vector<NewStage>& stages);
  std::vector<CampaignRecord> campaigns() const;
  std::optional<CampaignRecord> campaign(std::int64_t id) const;
  /// By id ("12") or by name (the newest campaign of that name).
  std::optional<CampaignRecord> find_campaign(const std::string& id_or_name) const;
  void set_campaign_state(std::int64_t id, const std::string& state, const std::string& error = "");
  std::vector<StageRecord> stages(std::int64_t campaign_id) const;
  /// A waiting stage starts: state running, with the trials its inputs selected (an array, or
  /// null without inputs) and its trial budget (which may depend on them), stored for good.
  void start_stage(std::int64_t stage_id, const Json& input_trials, std::int64_t budget_trials);
  /// done, or failed with the reason.
  void set_stage_state(std::int64_t stage_id, const std::string& state, const std::string& error = "");
  /// A stage's trial budget (`podium extend` raises a finished stage's).
  void set_stage_budget(std::int64_t stage_id, std::int64_t budget_trials);
  /// The search's state, the stage's active time and how many trials it has been told.
  void save_search_state(std::int64_t stage_id, const Json& state, double elapsed_s, std::int64_t told);

  // Trials and attempts.
  std::int64_t add_trial(std::int64_t stage_id, std::int64_t index, const Json& params, const Json& context, const Json& info,
                         std::uint64_t seed);
  std::vector<TrialRecord> trials(std::int64_t stage_id) const;
  std::vector<TrialRecord> campaign_trials(std::int64_t campaign_id) const;
  /// One trial (with its features), or nullopt.
  std::optional<TrialRecord> trial(std::int64_t trial_id) const;
  /// A stage's done trials in index order, lean (TrialOutcome): one walk of an index, no JSON
  /// parsed but the result info of trials whose info holds a per-task table.
  std::vector<TrialOutcome> done_trials(std::int64_t stage_id) const;
  /// The stage's strategy labels (StrategyLabels): per strategy the stage's counts hold, its first
  /// done trial in finishing order (one index probe each, schema v6).
  StrategyLabels strategy_labels(std::int64_t stage_id) const;
  TrialCounts trial_counts(std::int64_t campaign_id) const;
  /// Text that changes whenever a campaign's summary (store/summary.h) may: the campaign's state,
  /// its stages' states and budgets, their trial counts per state and per strategy, and each
  /// stage's latest finishing time (done trials never change, and a trial's strategy is stored
  /// with its result). A few count rows and one index probe per stage, whatever the trial count.
  std::string summary_token(std::int64_t campaign_id) const;
  TrialCounts stage_trial_counts(std::int64_t stage_id) const;
  std::int64_t start_attempt(std::int64_t trial_id, int number, const std::string& worker, const std::string& host,
                             const std::string& job_id = "");
  void finish_attempt(std::int64_t attempt_id, const std::string& state, const std::string& error, std::optional<int> exit_code,
                      std::optional<int> signal);
  /// Records a finished trial's result (state done), its features (named) and artifacts.
  void complete_trial(std::int64_t trial_id, const std::vector<double>& objectives, const std::vector<std::string>& feature_names,
                      const std::vector<double>& features, const Json& result_info, const std::vector<ArtifactRecord>& artifacts);
  /// Sets a trial's state (pending, failed, interrupted, cancelled) and, if given, its error text.
  void set_trial_state(std::int64_t trial_id, const std::string& state, const std::string& error = "");
  void set_trial_strategy(std::int64_t trial_id, std::int64_t strategy);
  /// Records where an attempt runs once known (a batch job id, the host it landed on).
  void set_attempt_placement(std::int64_t attempt_id, const std::string& job_id, const std::string& host);
  std::vector<AttemptRecord> attempts(std::int64_t trial_id) const;
  /// Attempts of a stage still running (where they run; batch jobs to re-attach to after a restart).
  std::vector<AttemptRecord> running_attempts(std::int64_t stage_id) const;
  std::vector<ArtifactRecord> artifacts(std::int64_t trial_id) const;

  // Metrics and events.
  /// Appends points; a point whose (name, step) the trial already has is dropped. A trial's series
  /// holds each step once: a resumed attempt (or a requeued Slurm job) re-sends the steps since its
  /// last checkpoint, and the first value sent for a step stays.
  void add_metrics(std::int64_t trial_id, const std::vector<MetricPoint>& points);
  std::vector<MetricPoint> metrics(std::int64_t trial_id) const;
  void add_event(std::int64_t campaign_id, const std::string& kind, const Json& payload);
  std::vector<Json> events(std::int64_t campaign_id) const;

  /// After a scheduler died: running attempts without a batch job id (they died with it) and
  /// their trials become interrupted. Returns how many. Batch jobs live on and are re-attached.
  int recover_interrupted();

 private:
  struct Impl;
  explicit Store(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Current time as unix seconds (the store's timestamps).
double now_unix_s();

/// A stage's state as shown to users: the stored one says where a scheduler resumes, so a running
/// stage of a paused or cancelled campaign shows "paused" or "cancelled", and a waiting stage of
/// a cancelled campaign "cancelled".
std::string shown_stage_state(const std::string& campaign_state, const std::string& stage_state);

/// The id of the campaign `id_or_name` names (an id, or the newest campaign of that name).
/// Throws base::UserError naming the database and the nearest campaign names when there is none.
std::int64_t find_campaign_id(const Store& store, const std::string& id_or_name);

/// A trial's one name, in every command and page: `<stage name>/<index>` ("explore/12"; the index
/// counts from 0 in the order the stage's search proposed). The database id is for URLs only.
std::string trial_name(const std::string& stage, std::int64_t index);

}  // namespace podium::store
