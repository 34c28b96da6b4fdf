#pragma once
/// Read-only queries for the dashboard and scripts: trial paging and filters, compact scatter
/// points, strategy summaries, downsampled metric series and a cheap change token.
///
/// A Queries object is one read-only connection (plus the typed reads of Store on another). Every
/// call reads one snapshot (its statements share one read transaction) that ends before it
/// returns, so no read transaction is held between calls and a running scheduler is never
/// blocked. One object per thread at a time.
///
/// Costs (schema v3): counts and summaries read the count rows the store's triggers keep and
/// min/max index probes, never all trials; pages and the scatter walk an index, not the table
/// (a large stage's scatter seeks its samples by index instead). Schema v6: a metric series is
/// read from an index alone, strategy labels are a probe per strategy, events their campaign's.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "podium/store/store.h"

namespace podium::store {

struct TrialFilter {
  std::optional<int> stage_index;        ///< only this stage (0-based)
  std::optional<std::string> state;      ///< only trials in this state
  std::optional<std::int64_t> strategy;  ///< only trials of this strategy cluster
  std::int64_t offset = 0, limit = 100;
  enum class Order { index, objective, finished } order = Order::index;
  bool descending = false;
};

/// A trial as a page lists it: TrialRecord's fields, with the JSON columns as the JSON text the
/// store wrote, so a page of 1,000 trials is written out without parsing and re-serialising them.
struct TrialText {
  std::int64_t id = 0, stage_id = 0, index = 0;
  std::uint64_t seed = 0;
  std::string state, error;
  int attempts = 0;
  std::string params, context, info, objectives, result_info;  ///< JSON text; "null" when absent
  std::vector<double> features;
  std::optional<std::int64_t> strategy;
  double created_at = 0, started_at = 0, finished_at = 0;
};

struct TrialPage {
  std::int64_t total = 0;  ///< trials matching the filter (before offset/limit)
  std::vector<TrialText> trials;
};

/// One finished trial as a point of the strategy-feature scatter (no params or metrics).
struct TrialPoint {
  std::int64_t id = 0, stage_index = 0, index = 0;
  double objective = 0;
  std::vector<double> features;
  std::optional<std::int64_t> strategy;
  std::string step;  ///< info.step ("explore", "diversity" for BDS) or ""
  double finished_at = 0;
};

/// Strategy ids are per stage (each stage groups its own trials), so a strategy is (stage, id).
struct StrategySummary {
  std::int64_t stage_index = 0, strategy = 0, trials = 0;
  std::int64_t label = 0;                 ///< what users read (StrategyLabels in store.h); `strategy` stays the key
  std::int64_t representative_trial = 0;  ///< the trial with the best objective (its id)
  std::int64_t representative_index = 0;  ///< and its index in the stage
  double best_objective = 0;
  std::vector<double> representative_features;
};

struct CampaignSummary {
  TrialCounts counts;
  std::map<std::int64_t, TrialCounts> stage_counts;  ///< by stage id (stages without trials absent)
  std::optional<double> best_objective;              ///< max of objectives[0] over done trials
  double first_finished_at = 0, last_finished_at = 0;
  std::int64_t done_last_minute = 0;            ///< trials finished in the 60 s before `now`
  std::vector<StrategySummary> strategy_table;  ///< what strategies() returns (same snapshot): per stage
};

/// One metric of one attempt, downsampled to at most 2 * max_points points (min and max of each
/// bucket, in step order, so spikes survive).
struct MetricSeries {
  std::string name;
  int attempt = 1;
  std::int64_t total_points = 0;
  std::vector<double> steps, values;  ///< NaN values are stored as NULL and returned as NaN
};

class Queries {
 public:
  /// Opens the database read-only (Store::open's checks apply). Throws base::RuntimeError.
  static std::unique_ptr<Queries> open(const std::filesystem::path& path);
  ~Queries();
  Queries(const Queries&) = delete;
  Queries& operator=(const Queries&) = delete;

  /// The typed reads of the store on this object's own read-only connection.
  const Store& store() const { return *store_; }

  /// Changes whenever another connection commits (SQLite's PRAGMA data_version); costs no I/O.
  std::int64_t data_version() const;

  std::optional<TrialRecord> trial(std::int64_t trial_id) const;
  /// The campaign a trial belongs to, or nullopt if there is no such trial.
  std::optional<std::int64_t> trial_campaign(std::int64_t trial_id) const;
  /// The id of a stage's trial number `index`, or nullopt if it has none.
  std::optional<std::int64_t> trial_id(std::int64_t stage_id, std::int64_t index) const;

  /// Counts, best objective, rates and the strategy table (count rows and index probes per stage).
  CampaignSummary summary(std::int64_t campaign_id, double now_unix_s) const;
  TrialPage trial_page(std::int64_t campaign_id, const TrialFilter& filter) const;
  /// Done trials as scatter points, in stage and trial index order; at most max_points per stage,
  /// evenly strided within a stage that has more (`total` receives the number of done trials).
  std::vector<TrialPoint> points(std::int64_t campaign_id, std::int64_t max_points, std::int64_t* total) const;
  /// Per stage in label order (StrategyLabels: 1..n in the order the strategies were found).
  std::vector<StrategySummary> strategies(std::int64_t campaign_id) const;
  /// Every metric (or only `name`) of a trial, each downsampled (see MetricSeries).
  std::vector<MetricSeries> metric_series(std::int64_t trial_id, std::int64_t max_points,
                                          const std::optional<std::string>& name) const;
  /// The campaign's last `last_n` events, oldest first (Store::events' entries: time, kind, payload).
  std::vector<Json> last_events(std::int64_t campaign_id, std::int64_t last_n) const;

 private:
  struct Impl;
  Queries(std::unique_ptr<Store> store, std::unique_ptr<Impl> impl);
  std::unique_ptr<Store> store_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace podium::store
